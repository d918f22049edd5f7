#!/usr/bin/python3
"""tools/impact_slopes.py on a bed whose answer is known: a train of sawtooth ripples (stoss 5 deg, lee 22
deg, 100 d long) hit by fast grains coming down at 15 deg, which by the shadow rule meet only the stoss,
evenly, and by slow grains spread evenly over the whole bed. Bad input exits 2.
usage: impact_slopes_test.py TOOLS_DIR WORK_DIR"""
import json
import math
import os
import subprocess
import sys

import h5py
import numpy as np

tools, work = sys.argv[1], sys.argv[2]
os.chdir(work)
LENGTH, WIDTH, DX, PERIOD = 400.0, 4.0, 0.5, 100.0
STOSS_DEG, LEE_DEG, DESCENT_DEG = 5.0, 22.0, 15.0
T_S, T_L = math.tan(math.radians(STOSS_DEG)), math.tan(math.radians(LEE_DEG))
STOSS = PERIOD * T_L / (T_S + T_L)  # its length, d (the crest at STOSS, 82.2 d)
x = np.arange(int(LENGTH / DX)) * DX
u = x % PERIOD
bed = np.where(u < STOSS, T_S * u, T_S * STOSS - T_L * (u - STOSS))
rng = np.random.default_rng(7)


def impacts(n, speed, descent_deg, stoss_only):
    """n impacts at even places over the stoss (or the whole bed), all at t* 1000-2000."""
    if stoss_only:
        xs = rng.integers(0, int(LENGTH / PERIOD), n) * PERIOD + rng.uniform(0, STOSS, n)
    else:
        xs = rng.uniform(0, LENGTH, n)
    a = math.radians(descent_deg)
    cols = {"t_star": rng.uniform(1000, 2000, n), "x": xs, "y": rng.uniform(0, WIDTH, n),
            "vx": speed * math.cos(a) * np.ones(n), "vy": np.zeros(n), "vz": -speed * math.sin(a) * np.ones(n),
            "nx": np.zeros(n), "ny": np.zeros(n), "nz": np.ones(n), "size_class": np.zeros(n),
            "speed": speed * np.ones(n), "descent_deg": descent_deg * np.ones(n)}
    return cols


def write(path, with_impacts=True):
    with h5py.File(path, "w") as f:
        f.attrs["dx"] = str(DX)
        g = f.create_group("frames")
        for k, t in enumerate([0.0, 1000.0, 2000.0]):
            d = g.create_dataset(f"{k:06d}", data=np.tile(bed, (int(WIDTH / DX), 1)))
            d.attrs["time"] = t
        if not with_impacts:
            return
        fast, slow = impacts(20000, 200.0, DESCENT_DEG, True), impacts(20000, 20.0, 40.0, False)
        names = list(fast)
        rows = np.vstack([np.column_stack([fast[n] for n in names]), np.column_stack([slow[n] for n in names])])
        d = f.create_dataset("impacts", data=rows)
        d.attrs["columns"] = ",".join(names)


def run(*args, expect=0):
    p = subprocess.run(["/usr/bin/python3", os.path.join(tools, "impact_slopes.py"), *args],
                       capture_output=True, text=True)
    assert p.returncode == expect, (args, p.returncode, p.stderr)
    return p


write("is-saw.h5")
r = json.loads(run("is-saw.h5", "--json", "--smooth", "1").stdout)
assert r["impacts"] == 40000 and r["frames"] == 2, r  # (t* 1000-2000 set on the frames at 1000 and 2000)
assert abs(r["descent_deg_fast"] - DESCENT_DEG) < 1e-9 and abs(r["fast_share"] - 0.5) < 1e-12, r
bins = {(b["slope_min_deg"], b["slope_max_deg"]): b for b in r["bins"]}
stoss, lee = bins[(3, 6)], bins[(-25, -20)]
share = STOSS / PERIOD  # of the bed; the smoothing over 1.5 d rounds the kinks only
assert abs(stoss["bed_share"] - share) < 0.03 and abs(lee["bed_share"] - (1 - share)) < 0.03, bins
# The fast grains meet only the stoss, evenly: 1 / share times the bed's mean rate there, none on the lee,
# as the shadow rule says; the slow ones meet both at the mean rate.
assert abs(stoss["rate_fast"] * share - 1) < 0.04 and lee["rate_fast"] == 0, (stoss, lee)
assert abs(stoss["rate_fast_shadow_rule"] * share - 1) < 0.04 and lee["rate_fast_shadow_rule"] == 0, (stoss, lee)
assert abs(stoss["rate_slow"] - 1) < 0.06 and abs(lee["rate_slow"] - 1) < 0.15, (stoss, lee)
assert abs(stoss["fast_descent_deg"] - DESCENT_DEG) < 1e-9 and lee["fast_descent_deg"] is None, (stoss, lee)
text = run("is-saw.h5").stdout
assert "| 3 to 6 |" in text and "15.0 deg over the fast ones" in text, text

write("is-none.h5", with_impacts=False)
assert "no /impacts" in run("is-none.h5", expect=2).stderr
assert "cannot be read" in run("is-missing.h5", expect=2).stderr
assert "must be positive" in run("is-saw.h5", "--smooth", "0", expect=2).stderr
print("impact_slopes: known bed read right; bad input refused")
