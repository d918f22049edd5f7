#!/usr/bin/python3
"""The mean ripple of a hybrid ripple run (`grainlab ripples hybrid --out RUN.h5`): its shape, and where the
bed erodes and grows on it.

A ripple's index is its length over its height, so why the index ends where it does is a question about
the ripple's shape: how steep its stoss (the upwind flank, rising to the crest) and its lee are, and which
part of it the splash cuts down or builds up. The autocorrelation's A and lambda average the shape away.
This tool keeps it. In the frame nearest --at T (the last frame but --span by default), each slice along x
is smoothed by a running mean over --smooth key points and its crests are found as in ripple_crests.py
(prominence at least --prominence d). Every ripple, from the trough upwind of a crest (the lowest point
between it and the crest before) through the crest to the trough downwind, is mapped onto a phase: 0 to
0.5 along the stoss, 0.5 to 1 along the lee, whatever their lengths. Averaged by phase over every ripple
of every slice:

- the mean ripple's height above the mean of its two troughs (d), phase by phase;
- the bed's change from that frame to the frame --span later (d), per 1,000 t* (per ejection per grain on
  the lattice bed): negative where the bed erodes, positive where it grows. A ripple moving downwind
  unchanged erodes its stoss at c tan(stoss) and builds its lee at c tan(lee), c its speed;
- the mean stoss and lee lengths (d) and the mean height; the flanks' mean angles from them, and the mean
  over the ripples of each flank's steepest slope between neighbouring key points (of the running mean).

The lattice bed of the thesis (`grainlab ripples lattice --out RUN.h5`) is read too: its one slice of
columns, heights in d, time in ejections per grain.

Usage:
  python3 tools/ripple_composite.py RUN.h5 [--at T] [--span K] [--bins N] [--json] [--plot OUT.png]
Exit status 2 for a missing or unreadable file, a checkpoint (it keeps the slice-averaged profiles only),
or a frame with no ripple.
"""
import argparse
import json
import math

import h5py
import numpy as np

import hybrid_wavelengths
from hybrid_wavelengths import fail
from ripple_crests import find_crests


LATTICE_COLUMN = math.sqrt(3) / 2  # a lattice-bed column in d (half a lattice spacing); a layer is d / 2


def read_frames(path):
    """(times, slices of each frame, the key points' spacing in d, the time's unit and how many of it the
    change is given per) of a `ripples hybrid --out` file (t*, per 1,000) or a `ripples lattice --out` file
    (ejections per grain, per one; its one slice of columns, heights turned from layers into d)."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: cannot be read as HDF5 ({e})")
    with f:
        if "h" in f and "history" in f and "frames" not in f:  # the lattice bed
            cols = f["history"].attrs["columns"]
            cols = (cols.decode() if isinstance(cols, bytes) else str(cols)).split(",")
            if "ejections_per_grain" not in cols or len(f["history"]) != len(f["h"]):
                fail(f"{path}: its /history does not give each frame's ejections per grain")
            times = f["history"][:, cols.index("ejections_per_grain")]
            beds = [0.5 * np.asarray(row, dtype=float)[None, :] for row in f["h"]]
            return times, beds, LATTICE_COLUMN, "ejections per grain", (1.0, "ejection per grain")
        if "frames" not in f or "dx" not in f.attrs:
            fail(f"{path}: no /frames: not a `ripples hybrid --out` or `ripples lattice --out` file (a "
                 "checkpoint keeps only the slice-averaged profiles)")
        names = sorted(f["frames"].keys())
        if not names:
            fail(f"{path}: /frames is empty")
        dx = f.attrs["dx"]
        dx = float(dx.decode() if isinstance(dx, bytes) else dx)
        times = np.array([float(f["frames"][n].attrs["time"]) for n in names])
        beds = [np.asarray(f["frames"][n][:], dtype=float) for n in names]
    return times, beds, dx, "t*", (1000.0, "1,000 t*")


def ripples_of(profile, dx, prominence, smooth):
    """(upwind trough, crest, downwind trough) key-point indices of each ripple of a periodic profile, on
    its running mean over `smooth` key points."""
    n = len(profile)
    s = hybrid_wavelengths.periodic_running_mean(profile, smooth)
    # find_crests places each crest between key points; its key point is the higher of the two around it,
    # so two crests are at least two key points apart and a trough lies between them
    crests = sorted({max(math.floor(x / dx) % n, math.ceil(x / dx) % n, key=lambda i: s[i])
                     for x, _ in find_crests(profile, dx, prominence, smooth)})
    if len(crests) < 2:
        return s, []
    troughs = []  # troughs[j]: the lowest point between crest j and crest j + 1
    for j, c in enumerate(crests):
        gap = (crests[(j + 1) % len(crests)] - c) % n
        troughs.append(min(((c + m) % n for m in range(1, gap)), key=lambda i: s[i]))
    return s, [(troughs[j - 1], c, troughs[j]) for j, c in enumerate(crests)]


def composite(before, after, dx, dt, per, bins, prominence, smooth):
    """The mean ripple of the frame `before` and the bed's change to `after`, dt later, per `per` of it.
    Each ripple is read at the phase bins' centres (interpolated between its key points) and counts once,
    whatever its length: averaging key points instead would weight the long ripples."""
    centres = (np.arange(bins) + 0.5) / bins
    height, change = np.zeros(bins), np.zeros(bins)
    stoss, lee, heights, steep_stoss, steep_lee = [], [], [], [], []
    for a, b in zip(before, after):
        s, ripples = ripples_of(a, dx, prominence, smooth)
        n = len(a)
        for up, crest, down in ripples:
            rise, fall = (crest - up) % n, (down - crest) % n
            at = [(up + m) % n for m in range(rise + fall + 1)]  # upwind trough, crest, downwind trough
            phase = [0.5 * m / rise if m <= rise else 0.5 + 0.5 * (m - rise) / fall for m in range(len(at))]
            base = 0.5 * (s[up] + s[down])
            height += np.interp(centres, phase, s[at] - base)
            change += np.interp(centres, phase, b[at] - a[at])
            slopes = np.diff(s[at]) / dx
            stoss.append(rise * dx), lee.append(fall * dx), heights.append(s[crest] - base)
            steep_stoss.append(slopes[:rise].max()), steep_lee.append(-slopes[rise:].min())
    if not heights:
        return None
    height /= len(heights)
    change *= per / dt / len(heights)
    h, ls, ll = float(np.mean(heights)), float(np.mean(stoss)), float(np.mean(lee))
    steepest_stoss, steepest_lee = float(np.mean(steep_stoss)), float(np.mean(steep_lee))
    return {
        "ripples": len(heights),
        "height": h,
        "stoss_length": ls,
        "lee_length": ll,
        "stoss_deg": math.degrees(math.atan2(h, ls)),
        "lee_deg": math.degrees(math.atan2(h, ll)),
        "steepest_stoss_deg": math.degrees(math.atan(steepest_stoss)),
        "steepest_lee_deg": math.degrees(math.atan(steepest_lee)),
        "phase": [(k + 0.5) / bins for k in range(bins)],
        "mean_height": [float(v) for v in height],
        "change": [float(v) for v in change],
    }


def plot(result, path, title):
    import os

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.5, 5), sharex=True)
    top.plot(result["phase"], result["mean_height"], "k.-")
    top.set_ylabel("height above the troughs (d)")
    top.set_title(f"{title}\nstoss {result['stoss_length']:.1f} d ({result['stoss_deg']:.1f} deg), "
                  f"lee {result['lee_length']:.1f} d ({result['lee_deg']:.1f} deg)", fontsize=9)
    bottom.bar(result["phase"], result["change"], width=0.8 / len(result["phase"]), color="tab:blue")
    bottom.axhline(0, color="k", lw=0.6)
    bottom.set_ylabel(f"bed change per {result['change_per']} (d)")
    bottom.set_xlabel("phase: 0 upwind trough, 0.5 crest, 1 downwind trough")
    for ax in (top, bottom):
        ax.axvline(0.5, color="0.7", lw=0.8)
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--at", type=float, help="time of the frame, t* or ejections per grain (the nearest is taken); default: the last but --span")
    ap.add_argument("--span", type=int, default=2, help="frames between the two beds compared (2)")
    ap.add_argument("--bins", type=int, default=20, help="phase bins, even (20)")
    ap.add_argument("--prominence", type=float, default=1.0, help="least crest height in d (1)")
    ap.add_argument("--smooth", type=int, default=5, help="running mean over this many key points, odd (5)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--plot", help="write the mean ripple and the bed's change to this PNG")
    a = ap.parse_args()
    if a.span < 1 or a.bins < 4 or a.bins % 2 or a.prominence <= 0 or a.smooth < 1 or a.smooth % 2 == 0:
        fail("--span must be at least 1, --bins even and at least 4, --prominence positive, --smooth odd")
    times, beds, dx, unit, (per, per_label) = read_frames(a.file)
    if len(beds) <= a.span:
        fail(f"{a.file}: {len(beds)} frames, need more than --span {a.span}")
    k = len(beds) - 1 - a.span if a.at is None else int(np.argmin(np.abs(times - a.at)))
    k = min(k, len(beds) - 1 - a.span)
    result = composite(beds[k], beds[k + a.span], dx, times[k + a.span] - times[k], per, a.bins,
                       a.prominence, a.smooth)
    if result is None:
        fail(f"{a.file}: no slice has two crests {a.prominence:g} d proud at {unit} = {times[k]:g}")
    result = {"file": a.file, "time_unit": unit, "at": float(times[k]), "after": float(times[k + a.span]),
              "change_per": per_label, **result}
    if a.plot:
        plot(result, a.plot, f"{a.file}, {unit} = {times[k]:g}: {result['ripples']} ripples")
    if a.json:
        print(json.dumps(result))
        return
    print(f"{a.file} at {unit} = {times[k]:g}: {result['ripples']} ripples, height {result['height']:.2f} d, "
          f"stoss {result['stoss_length']:.1f} d ({result['stoss_deg']:.1f} deg, steepest "
          f"{result['steepest_stoss_deg']:.1f}), lee {result['lee_length']:.1f} d ({result['lee_deg']:.1f} deg, "
          f"steepest {result['steepest_lee_deg']:.1f})")
    print(f"phase  height (d)  change per {result['change_per']} (d)")
    for p, h, c in zip(result["phase"], result["mean_height"], result["change"]):
        print(f"{p:5.3f}  {h:10.2f}  {c:+9.4f}")


if __name__ == "__main__":
    main()
