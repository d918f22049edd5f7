"""The splash files shipped in data/splash are the ones its README lists, and the models run on them.

Usage: shipped_splash_test.py GRAINLAB SOURCE_DIR. Checks every file against the checksum the README
gives (a file replaced without its README fails), that each records the command the README says made it,
and runs the models the README names on them, from the source directory as a user would: the hybrid
preset (scenes/ripples/hybrid_measured_splash.toml) for 250 t*, a flat-bed flux run on the 3-D file and
the Ch. IV wind model on the 2-D file.
"""
import hashlib
import json
import os
import re
import subprocess
import sys

import h5py

grainlab, source = sys.argv[1], sys.argv[2]
folder = os.path.join(source, "data", "splash")
readme = open(os.path.join(folder, "README.md")).read()

listed = dict((name, digest) for digest, name in re.findall(r"^([0-9a-f]{64})  (\S+\.h5)$", readme, re.M))
shipped = sorted(f for f in os.listdir(folder) if f.endswith(".h5"))
assert sorted(listed) == shipped, f"README lists {sorted(listed)}, data/splash holds {shipped}"
for name, digest in listed.items():
    with open(os.path.join(folder, name), "rb") as f:
        assert hashlib.sha256(f.read()).hexdigest() == digest, f"{name}: not the file the README lists"


def text(attrs, key):
    v = attrs[key]
    return v.decode() if isinstance(v, bytes) else str(v)


with h5py.File(os.path.join(folder, "spheres3d_wide.h5")) as f:
    assert text(f.attrs, "schema") == "grainlab-splash/1" and int(f.attrs["dimension"]) == 3
    assert text(f.attrs, "active_zone") == "the grains within 12 diameters", text(f.attrs, "active_zone")
    assert "6000 spheres in a 67.3 x 60 cm box" in text(f.attrs, "source"), text(f.attrs, "source")
    assert len(f["cells"]) == 16 and all(int(c.attrs["impacts"]) == 40 for c in f["cells"].values())
with h5py.File(os.path.join(folder, "discs2d.h5")) as f:
    assert text(f.attrs, "schema") == "grainlab-splash/1" and int(f.attrs.get("dimension", 2)) == 2
    assert len(f["cells"]) == 25 and all(int(c.attrs["impacts"]) == 20 for c in f["cells"].values())


def run(*args):
    out = subprocess.run([grainlab, *args, "--json"], cwd=source, capture_output=True, text=True)
    assert out.returncode == 0, f"{' '.join(args)}: exit {out.returncode}\n{out.stderr}"
    return json.loads(out.stdout)


ripples = run("ripples", "hybrid", "--config", "scenes/ripples/hybrid_measured_splash.toml", "--duration", "250",
              "--quiet")
assert ripples["mass_flux_star"] > 0 and abs(ripples["t_star"] - 250) < 1, ripples
flux = run("ripples", "hybrid-flux", "--ustar", "40", "--swept", "--travel", "1.5", "--duration", "300",
           "--average-from", "150", "--splash", "data/splash/spheres3d_wide.h5")
assert flux["mass_flux_star"] > 0 and flux["splash"] == "data/splash/spheres3d_wide.h5", flux
wind = run("saltation", "wind", "--splash", "data/splash/discs2d.h5", "--ustar", "40")
assert wind["converged"] and 0 < wind["u_star_eff"] < 40, wind
print("shipped splash files: checksums, provenance and three model runs agree")
