"""Damaged checkpoints are refused by name or continued, never a crash and never a half-written output.

Usage: checkpoint_fuzz_test.py GRAINLAB CHECKPOINT MUTANTS SEED ARG... where the ARGs continue a run from a
checkpoint, with the word MUTANT where the damaged copy's path goes and OUT where an output file's (if the
command writes one). The checkpoint is read once, whole; each mutant flips 1-3 bytes of it at seeded places
(the scene reader's fuzz tests do the same to scenes). Every continued run must end with exit status 0
(the damage fell where nothing is read, or on a value the run accepts) or 2 with a message that names the
file, and a refused run must leave no output file behind, finished or temporary. A continued run must
end where the undamaged checkpoint's continuation ends: the same JSON on stdout (wall times aside) and
the same output file (h5diff, root attributes and /diagnostics aside), so that damage the reader lets
through cannot change a result unseen. A crash (a signal, or an exit status other than 0 and 2) fails the
test and prints the seed and mutant that caused it.
"""
import json
import os
import random
import subprocess
import sys
import tempfile

grainlab, checkpoint, mutants, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
template = sys.argv[5:]
original = open(checkpoint, "rb").read()
rng = random.Random(seed)
refused = continued = 0


def result(stdout):
    """The JSON a run printed, less what depends on the machine's speed (or the text, if not JSON)."""
    try:
        j = json.loads(stdout)
    except ValueError:
        return stdout
    if isinstance(j, dict):
        for k in [k for k in j if "wall" in k or "seconds" in k or k.endswith("per_second")]:
            j.pop(k)
    return j


def same_file(a, b):
    if not os.path.exists(a) and not os.path.exists(b):
        return True
    return subprocess.run(["h5diff", "--exclude-attribute", "/", "--exclude-attribute", "/diagnostics", a, b],
                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0


with tempfile.TemporaryDirectory() as d:
    mutant, out, reference = (os.path.join(d, f) for f in ("mutant.h5", "out.h5", "reference.h5"))
    args = [mutant if a == "MUTANT" else out if a == "OUT" else a for a in template]
    with open(mutant, "wb") as f:
        f.write(original)
    ref = subprocess.run([grainlab] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)
    assert ref.returncode == 0, f"the undamaged checkpoint does not continue:\n{ref.stderr}"
    expected = result(ref.stdout)
    if os.path.exists(out):
        os.rename(out, reference)
    for f in os.listdir(d):  # (e.g. a run's XDMF or plot beside its HDF5)
        if f.startswith("out"):
            os.remove(os.path.join(d, f))
    for k in range(mutants):
        damaged = bytearray(original)
        for _ in range(rng.randint(1, 3)):
            damaged[rng.randrange(len(damaged))] ^= rng.randint(1, 255)
        with open(mutant, "wb") as f:
            f.write(damaged)
        # (The mutant is rewritten by a continued run that checkpoints into it: each mutant starts afresh.)
        run = subprocess.run([grainlab] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             timeout=300)
        left = [f for f in os.listdir(d) if f.startswith("out") or ".tmp-" in f]
        if run.returncode == 2:
            refused += 1
            assert "mutant.h5" in run.stderr, f"mutant {k} (seed {seed}): refused without naming the file:\n{run.stderr}"
            assert not left, f"mutant {k} (seed {seed}): refused, but left {left}"
        elif run.returncode == 0:
            continued += 1
            assert result(run.stdout) == expected, f"mutant {k} (seed {seed}): continued to another result"
            assert same_file(out, reference), f"mutant {k} (seed {seed}): continued to another output file"
        else:
            sys.exit(f"mutant {k} (seed {seed}): exit status {run.returncode}\n{run.stderr}")
        for f in left:
            os.remove(os.path.join(d, f))
print(f"{mutants} damaged copies of {os.path.basename(checkpoint)}: {refused} refused by name, {continued} continued")
assert refused > 0, "no damaged copy was refused: the reader checks nothing"
