#!/usr/bin/python3
"""tools/ripple_composite.py on a bed whose answer is known: a train of asymmetric sawtooth ripples (stoss
75 d long, lee 25 d, 5 d high) moving downwind unchanged at 1e-3 d per t*, so that the stoss erodes at
c tan(stoss) and the lee grows at c tan(lee). Bad input exits 2.
usage: ripple_composite_test.py TOOLS_DIR WORK_DIR"""
import json
import math
import os
import subprocess
import sys

import h5py
import numpy as np

tools, work = sys.argv[1], sys.argv[2]
os.chdir(work)
LENGTH, DX, EVERY, SPEED = 400.0, 0.5, 500.0, 1e-3
STOSS, LEE, HEIGHT = 75.0, 25.0, 5.0
x = np.arange(int(LENGTH / DX)) * DX


def sawtooth(t):
    u = (x - SPEED * t) % (STOSS + LEE)  # 0 at a trough, STOSS at the crest
    return np.where(u < STOSS, HEIGHT * u / STOSS, HEIGHT * (STOSS + LEE - u) / LEE)


def write(path, surface, t_end, with_frames=True):
    times = np.arange(0, t_end + EVERY / 2, EVERY)
    with h5py.File(path, "w") as f:
        if not with_frames:  # a checkpoint keeps no frames
            f.attrs["kind"] = "grainlab-hybrid-ripples-checkpoint/1"
            return
        f.attrs["dx"] = str(DX)
        g = f.create_group("frames")
        for k, t in enumerate(times):
            d = g.create_dataset(f"{k:06d}", data=np.tile(surface(t), (3, 1)))
            d.attrs["time"] = t


def run(*args, expect=0):
    p = subprocess.run(["/usr/bin/python3", os.path.join(tools, "ripple_composite.py"), *args],
                       capture_output=True, text=True)
    assert p.returncode == expect, (args, p.returncode, p.stderr)
    return p


write("cm-saw.h5", sawtooth, 5000)
r = json.loads(run("cm-saw.h5", "--json", "--at", "2000").stdout)
assert r["ripples"] == 12 and r["at"] == 2000 and r["after"] == 3000 and r["change_per"] == "1,000 t*", r  # 4 per slice, 3 slices
# Crests and troughs are found on the running mean over 5 key points (2.5 d), which moves a sharp crest
# toward the gentle flank by up to half of that: lengths within 1.25 d, the angles within what that and
# the rounded height allow. Each flank's steepest slope is the running mean's on its straight middle,
# the flank's own. The height is rounded at the crest and the troughs by 2 x 2 a, a the stoss's rise per
# key point (1/30 d).
assert abs(r["stoss_length"] - STOSS) <= 1.25 and abs(r["lee_length"] - LEE) <= 1.25, r
assert HEIGHT - 4 / 30 - 1e-9 <= r["height"] <= HEIGHT, r


def angle_within(value, rise, run):  # the angle the rounded height and the moved ends allow
    low, high = math.atan((rise - 4 / 30) / (run + 1.25)), math.atan(rise / (run - 1.25))
    return math.degrees(low) <= value <= math.degrees(high)


assert angle_within(r["stoss_deg"], HEIGHT, STOSS) and angle_within(r["lee_deg"], HEIGHT, LEE), r
assert abs(r["steepest_lee_deg"] - math.degrees(math.atan(HEIGHT / LEE))) < 1e-6, r
assert abs(r["steepest_stoss_deg"] - math.degrees(math.atan(HEIGHT / STOSS))) < 1e-6, r
# mid-flank bins, away from the crest and the troughs that the 1 d of travel rounds: erosion of
# c tan(stoss) = 0.0667 d and growth of c tan(lee) = 0.2 d per 1,000 t*
phase, change = np.array(r["phase"]), np.array(r["change"])
stoss = change[(phase > 0.1) & (phase < 0.4)]
lee = change[(phase > 0.65) & (phase < 0.9)]
assert np.all(np.abs(stoss + 1000 * SPEED * HEIGHT / STOSS) < 0.002), stoss
assert np.all(np.abs(lee - 1000 * SPEED * HEIGHT / LEE) < 0.01), lee
assert "height" in run("cm-saw.h5").stdout and run("cm-saw.h5", "--plot", "cm.png") and os.path.getsize("cm.png") > 0

# The lattice bed's file: one slice of columns (sqrt(3) d / 2 each), heights in layers (d / 2), frames in
# ejections per grain. The same train, its x and heights in those units, moving 0.05 d per ejection.
COLUMN = math.sqrt(3) / 2
with h5py.File("cm-lattice.h5", "w") as f:
    times = np.arange(0, 10.5, 1.0)
    x_lattice = np.arange(int(LENGTH / COLUMN)) * COLUMN
    f.create_dataset("h", data=[2 * np.interp((x_lattice - 0.05 * t) % (STOSS + LEE), [0, STOSS, STOSS + LEE],
                                                [0, HEIGHT, 0]) for t in times])
    f.create_dataset("history", data=np.c_[times, np.zeros(len(times))]).attrs["columns"] = \
        "ejections_per_grain,roughness"
lattice = json.loads(run("cm-lattice.h5", "--json", "--at", "4").stdout)
assert lattice["change_per"] == "ejection per grain" and lattice["after"] == 6, lattice
assert abs(lattice["stoss_length"] - STOSS) <= 2.5 * COLUMN and abs(lattice["lee_length"] - LEE) <= 2.5 * COLUMN, lattice
phase, change = np.array(lattice["phase"]), np.array(lattice["change"])
assert np.all(np.abs(change[(phase > 0.1) & (phase < 0.4)] + 0.05 * HEIGHT / STOSS) < 0.002), lattice

# Bad input: a missing file, a checkpoint, a flat bed, an odd number of bins.
assert "cannot be read" in run("cm-none.h5", expect=2).stderr
write("cm-ck.h5", sawtooth, 0, with_frames=False)
assert "no /frames" in run("cm-ck.h5", expect=2).stderr
write("cm-flat.h5", lambda t: 0 * x, 2000)
assert "no slice has two crests" in run("cm-flat.h5", expect=2).stderr
assert "--bins even" in run("cm-saw.h5", "--bins", "7", expect=2).stderr
print("ripple_composite: sawtooth train and bad input as expected")
