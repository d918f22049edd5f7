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
- the bed's change from that frame to the frame --span later, per 1,000 t* (d): negative where the bed
  erodes, positive where it grows. A ripple moving downwind unchanged erodes its stoss at c tan(stoss)
  and builds its lee at c tan(lee), c its speed;
- the mean stoss and lee lengths (d) and the mean height; the flanks' mean angles from them, and the
  steepest slope of the mean ripple on each flank.

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


def read_frames(path):
    """(times, slices of each frame) and the key points' spacing (d) of a `ripples hybrid --out` file."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: cannot be read as HDF5 ({e})")
    with f:
        if "frames" not in f or "dx" not in f.attrs:
            fail(f"{path}: no /frames: not a `ripples hybrid --out` file (a checkpoint keeps only the "
                 "slice-averaged profiles)")
        names = sorted(f["frames"].keys())
        if not names:
            fail(f"{path}: /frames is empty")
        dx = f.attrs["dx"]
        dx = float(dx.decode() if isinstance(dx, bytes) else dx)
        times = np.array([float(f["frames"][n].attrs["time"]) for n in names])
        beds = [np.asarray(f["frames"][n][:], dtype=float) for n in names]
    return times, beds, dx


def ripples_of(profile, dx, prominence, smooth):
    """(upwind trough, crest, downwind trough) key-point indices of each ripple of a periodic profile, on
    its running mean over `smooth` key points."""
    n = len(profile)
    s = hybrid_wavelengths.periodic_running_mean(profile, smooth)
    crests = sorted({int(round(x / dx)) % n for x, _ in find_crests(profile, dx, prominence, smooth)})
    if len(crests) < 2:
        return s, []
    troughs = []  # troughs[j]: the lowest point between crest j and crest j + 1
    for j, c in enumerate(crests):
        gap = (crests[(j + 1) % len(crests)] - c) % n
        troughs.append(min(((c + m) % n for m in range(1, gap)), key=lambda i: s[i]))
    return s, [(troughs[j - 1], c, troughs[j]) for j, c in enumerate(crests)]


def composite(before, after, dx, dt, bins, prominence, smooth):
    """The mean ripple of the frame `before` and the bed's change to `after`, dt t* later."""
    height, change, count = np.zeros(bins), np.zeros(bins), np.zeros(bins)
    stoss, lee, heights = [], [], []
    for a, b in zip(before, after):
        s, ripples = ripples_of(a, dx, prominence, smooth)
        n = len(a)
        for up, crest, down in ripples:
            rise, fall = (crest - up) % n, (down - crest) % n
            base = 0.5 * (s[up] + s[down])
            stoss.append(rise * dx), lee.append(fall * dx), heights.append(s[crest] - base)
            for m in range(rise + fall):  # the key points from the upwind trough to the crest, then on
                i = (up + m) % n
                phase = 0.5 * m / rise if m < rise else 0.5 + 0.5 * (m - rise) / fall
                k = min(bins - 1, int(phase * bins))
                height[k] += s[i] - base
                change[k] += b[i] - a[i]
                count[k] += 1
    if not heights:
        return None
    seen = count > 0
    height[seen] /= count[seen]
    change[seen] *= 1000 / dt / count[seen]
    height[~seen], change[~seen] = math.nan, math.nan
    h, ls, ll = float(np.mean(heights)), float(np.mean(stoss)), float(np.mean(lee))
    # The steepest slope of the mean ripple on each flank: its height's steps over the phase bins, each
    # bin a share of that flank's mean length.
    step = np.diff(height)
    half = bins // 2
    steepest_stoss = np.nanmax(step[:half - 1]) / (ls * 2 / bins) if half > 1 else math.nan
    steepest_lee = -np.nanmin(step[half:]) / (ll * 2 / bins) if half > 1 else math.nan
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
        "mean_height": [None if math.isnan(v) else float(v) for v in height],
        "change_per_1000": [None if math.isnan(v) else float(v) for v in change],
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
    bottom.bar(result["phase"], result["change_per_1000"], width=0.8 / len(result["phase"]), color="tab:blue")
    bottom.axhline(0, color="k", lw=0.6)
    bottom.set_ylabel("bed change per 1,000 t* (d)")
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
    ap.add_argument("--at", type=float, help="t* of the frame (the nearest is taken); default: the last but --span")
    ap.add_argument("--span", type=int, default=2, help="frames between the two beds compared (2)")
    ap.add_argument("--bins", type=int, default=20, help="phase bins, even (20)")
    ap.add_argument("--prominence", type=float, default=1.0, help="least crest height in d (1)")
    ap.add_argument("--smooth", type=int, default=5, help="running mean over this many key points, odd (5)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--plot", help="write the mean ripple and the bed's change to this PNG")
    a = ap.parse_args()
    if a.span < 1 or a.bins < 4 or a.bins % 2 or a.prominence <= 0 or a.smooth < 1 or a.smooth % 2 == 0:
        fail("--span must be at least 1, --bins even and at least 4, --prominence positive, --smooth odd")
    times, beds, dx = read_frames(a.file)
    if len(beds) <= a.span:
        fail(f"{a.file}: {len(beds)} frames, need more than --span {a.span}")
    k = len(beds) - 1 - a.span if a.at is None else int(np.argmin(np.abs(times - a.at)))
    k = min(k, len(beds) - 1 - a.span)
    result = composite(beds[k], beds[k + a.span], dx, times[k + a.span] - times[k], a.bins, a.prominence,
                       a.smooth)
    if result is None:
        fail(f"{a.file}: no slice has two crests {a.prominence:g} d proud at t* = {times[k]:.0f}")
    result = {"file": a.file, "t_star": float(times[k]), "t_star_after": float(times[k + a.span]), **result}
    if a.plot:
        plot(result, a.plot, f"{a.file}, t* = {times[k]:.0f}: {result['ripples']} ripples")
    if a.json:
        print(json.dumps(result))
        return
    print(f"{a.file} at t* = {result['t_star']:.0f}: {result['ripples']} ripples, height {result['height']:.2f} d, "
          f"stoss {result['stoss_length']:.1f} d ({result['stoss_deg']:.1f} deg, steepest "
          f"{result['steepest_stoss_deg']:.1f}), lee {result['lee_length']:.1f} d ({result['lee_deg']:.1f} deg, "
          f"steepest {result['steepest_lee_deg']:.1f})")
    print("phase  height (d)  change per 1,000 t* (d)")
    for p, h, c in zip(result["phase"], result["mean_height"], result["change_per_1000"]):
        print(f"{p:5.3f}  {h:10.2f}  {c:+8.3f}")


if __name__ == "__main__":
    main()
