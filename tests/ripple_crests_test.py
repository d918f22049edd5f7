#!/usr/bin/python3
"""tools/ripple_crests.py on beds whose answers are known: a train of equal sine ripples moving at a set speed
(no merger, the speed, equal heights), and two Gaussian bumps of which the lower and faster one catches the
higher one (one merger, speed falling with height), beside a third that is never caught. Bad input exits 2.
usage: ripple_crests_test.py TOOLS_DIR WORK_DIR"""
import json
import os
import subprocess
import sys

import h5py
import numpy as np

tools, work = sys.argv[1], sys.argv[2]
os.chdir(work)
LENGTH, DX, EVERY = 400.0, 0.5, 500.0
x = np.arange(int(LENGTH / DX)) * DX


def write(path, surface, t_end):
    """A `ripples hybrid --out` file in outline: frames (4 slices across, x fastest) with their t*, the
    history table with its columns, and the key points' spacing."""
    times = np.arange(0, t_end + EVERY / 2, EVERY)
    with h5py.File(path, "w") as f:
        f.attrs["dx"] = str(DX)
        g = f.create_group("frames")
        for k, t in enumerate(times):
            d = g.create_dataset(f"{k:06d}", data=np.tile(surface(t), (4, 1)))
            d.attrs["time"] = t
        h = f.create_dataset("history", data=np.c_[times, np.full(len(times), 100.0)])
        h.attrs["columns"] = "t_star,wavelength"


def run(*args, expect=0):
    p = subprocess.run(["/usr/bin/python3", os.path.join(tools, "ripple_crests.py"), *args],
                       capture_output=True, text=True)
    assert p.returncode == expect, (args, p.returncode, p.stderr)
    return p


def periodic_gap(a, b):
    return (a - b + LENGTH / 2) % LENGTH - LENGTH / 2


def bump(t, x0, height, speed, width=6.0):
    return height * np.exp(-0.5 * (periodic_gap(x, x0 + speed * t) / width) ** 2)


# Four equal sine ripples, 100 d long and 3 d high, moving downwind at 1e-3 d per t*.
write("rc-train.h5", lambda t: 3 * np.sin(2 * np.pi * (x - 1e-3 * t) / 100), 40000)
train = json.loads(run("rc-train.h5", "--json").stdout)["runs"][0]
assert train["crests_start"] == 4 and train["crests_end"] == 4 and train["mergers"] == 0, train
assert abs(train["speed"] - 1e-3) < 0.02e-3, train
assert train["height_cv"] < 0.01, train

# A bump 1.5 d high at x = 150 moving at 3e-3 catches one 4 d high at x = 200 moving at 1e-3 (they meet
# at t* = 25,000); one 3 d high at x = 330 moving at 1e-3 stays ahead of both.
write("rc-merge.h5", lambda t: bump(t, 150, 1.5, 3e-3) + bump(t, 200, 4, 1e-3) + bump(t, 330, 3, 1e-3), 28000)
merge = json.loads(run("rc-merge.h5", "--json", "--span", "10").stdout)["runs"][0]
assert merge["crests_start"] == 3 and merge["crests_end"] == 2 and merge["mergers"] == 1, merge
assert merge["beta"] < -0.5, merge  # the lower crest is the faster (speeds 3e-3 and 1e-3: -1.1 apart)

# Two files pooled: mergers summed, the rest averaged with a standard error.
pooled = json.loads(run("rc-train.h5", "rc-merge.h5", "--json", "--span", "10").stdout)["pooled"]
assert pooled["files"] == 2 and pooled["mergers"] == 1 and pooled["crests_start"] == 3.5, pooled

# Bad input: a missing file, a window without frames, an even smoothing.
assert "cannot be read" in run("rc-none.h5", expect=2).stderr
assert "frames in t*" in run("rc-train.h5", "--window", "90000", "95000", expect=2).stderr
assert "--smooth odd" in run("rc-train.h5", "--smooth", "4", expect=2).stderr
print("ripple_crests: train, merger, pooling and bad input as expected")
