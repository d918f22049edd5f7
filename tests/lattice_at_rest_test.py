#!/usr/bin/env python3
"""bench/lattice_at_rest.py writes a lattice that stands still: each layer pressed into the one below by
the weight it carries. Run on the engine for 500 steps, its kinetic energy stays at round-off, while the
same lattice with every layer at its unpressed height (centres 2 r apart) starts to oscillate; its
mean height is the one the script computed. Bad sizes are refused with exit status 2.

usage: lattice_at_rest_test.py BENCH_DIR GRAINLAB WORK_DIR
"""
import json
import os
import subprocess
import sys

bench_dir, grainlab, work = sys.argv[1:4]
sys.path.insert(0, bench_dir)
import lattice_at_rest as lat  # noqa: E402

script = os.path.join(bench_dir, "lattice_at_rest.py")
scene = os.path.join(work, "lar-rest.toml")
subprocess.run([sys.executable, script, "6", "6", "5", scene], check=True)


def run(path):
    out = os.path.join(work, "lar.json")
    subprocess.run([grainlab, "bench", "bed3d", "--bed-scene", path, "--steps", "500", "--repeats", "1", "--json",
                    out], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        return json.load(f)


rest = run(scene)
zs = lat.heights(5)
expected_height = sum(zs) / len(zs)
assert rest["spheres"] == 180, rest
assert rest["kinetic_energy"] < 1e-9, f"the pressed lattice moves: {rest['kinetic_energy']} erg"
assert abs(rest["mean_height"] - expected_height) < 1e-9, (rest["mean_height"], expected_height)

# The control: the same lattice with its layers at 1, 3, 5, ... cm.
text = open(scene).read()
for k, z in enumerate(zs):
    text = text.replace(f", {z!r}]", f", {1.0 + 2.0 * k!r}]")
loose = os.path.join(work, "lar-loose.toml")
with open(loose, "w") as f:
    f.write(text)
moving = run(loose)
assert moving["kinetic_energy"] > 1e-3, f"the unpressed lattice should settle: {moving['kinetic_energy']} erg"

bad = subprocess.run([sys.executable, script, "6", "0", "5", os.path.join(work, "lar-bad.toml")],
                     capture_output=True, text=True)
assert bad.returncode == 2 and "ny must be at least 1" in bad.stderr, (bad.returncode, bad.stderr)
assert not os.path.exists(os.path.join(work, "lar-bad.toml"))
print(f"pressed: {rest['kinetic_energy']:.3g} erg; unpressed: {moving['kinetic_energy']:.3g} erg")
