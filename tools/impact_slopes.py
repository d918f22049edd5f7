#!/usr/bin/python3
"""Where the grains of a hybrid ripple run hit the bed: the impact rate by the bed's slope along the wind.

A grain coming down at an angle a below the horizontal cannot reach a lee face steeper than a: the face is
in the shadow of the crest. On a gentler face, and on a stoss, it meets the bed per unit of horizontal area
at 1 + tan(b) / tan(a) times its rate on a level bed (b the face's slope along the wind, positive rising
downwind). Whether a ripple's lee is shadowed, and from which grains, decides what builds it.

This tool reads a run made with `grainlab ripples hybrid ... --out RUN.h5 --impacts-from T` (the table
/impacts and the bed frames). Each impact is set on the frame nearest its time; each slice of that frame
along x is smoothed by a running mean over --smooth d, and the impact takes the slope of the smoothed slice
where it met the bed. By slope bin:

- the share of the bed's key points with that slope (over the frames the impacts were set on, each frame
  counted as often as it took impacts);
- the impact rate per key point, over the bed's mean rate, for all impacts, for the fast ones (speed above
  --fast cm/s: the saltating grains) and for the slow ones (below --slow cm/s: the ejecta's short hops);
- the same rate for the fast impacts as the shadow rule gives it, max(0, 1 + tan(b) / tan(a)) with a the
  fast impacts' mean descent angle, over its mean on the same key points;
- the fast impacts' mean descent angle in the bin.

Usage:
  python3 tools/impact_slopes.py RUN.h5 [--smooth D] [--fast V] [--slow V] [--json] [--plot OUT.png]
Exit status 2 for a missing or unreadable file, or one without /impacts.
"""
import argparse
import json
import math

import h5py
import numpy as np

from hybrid_wavelengths import fail, periodic_running_mean
from ripple_composite import read_frames

EDGES_DEG = [-40, -25, -20, -15, -12, -9, -6, -3, 0, 3, 6, 9, 12, 15, 20, 25, 40]


def read_impacts(path):
    """The /impacts table of a `ripples hybrid --impacts-from` file as a dict of columns."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: cannot be read as HDF5 ({e})")
    with f:
        if "impacts" not in f:
            fail(f"{path}: no /impacts table: run `grainlab ripples hybrid` with --impacts-from T")
        names = f["impacts"].attrs["columns"]
        names = (names.decode() if isinstance(names, bytes) else str(names)).split(",")
        data = np.asarray(f["impacts"][:], dtype=float).reshape(-1, len(names))
    wanted = ["t_star", "x", "y", "speed", "descent_deg"]
    if any(w not in names for w in wanted):
        fail(f"{path}: /impacts lacks one of the columns {wanted}")
    if len(data) == 0:
        fail(f"{path}: /impacts is empty")
    return {n: data[:, names.index(n)] for n in wanted}


def slopes_of(bed, dx, smooth_d):
    """dh/dx (d per d) of each slice of a frame (ny x nx, periodic), on its running mean over smooth_d."""
    width = max(1, int(round(smooth_d / dx)))
    width += 1 - width % 2  # odd
    s = np.array([periodic_running_mean(row, width) for row in bed])
    return (np.roll(s, -1, axis=1) - np.roll(s, 1, axis=1)) / (2 * dx)


def nearest(times, t):
    """The index of the time in `times` (ascending) nearest each of `t`, without a len(t) x len(times)
    table (a long log on the paper's domain has millions of impacts and a hundred frames)."""
    hi = np.clip(np.searchsorted(times, t), 1, len(times) - 1)
    lo = hi - 1
    return np.where(t - times[lo] <= times[hi] - t, lo, hi) if len(times) > 1 else np.zeros(len(t), int)


def analyse(path, smooth_d, fast, slow):
    times, beds, dx, unit, _ = read_frames(path)
    if unit != "t*":
        fail(f"{path}: not a hybrid ripple run")
    imp = read_impacts(path)
    frame_of = nearest(times, imp["t_star"])
    used = np.unique(frame_of)
    slope_at = np.empty(len(frame_of))
    bed_slopes, weights = [], []
    for k in used:
        s = slopes_of(beds[k], dx, smooth_d)
        ny, nx = s.shape
        mine = frame_of == k
        # Linear along x between key points, nearest slice across (key point i sits at x = i dx).
        u = imp["x"][mine] / dx
        i0 = np.floor(u).astype(int) % nx
        w = u - np.floor(u)
        j = np.rint(imp["y"][mine] / dx).astype(int) % ny
        slope_at[mine] = (1 - w) * s[j, i0] + w * s[j, (i0 + 1) % nx]
        bed_slopes.append(s.ravel())
        weights.append(np.full(s.size, mine.sum() / s.size))
    bed_slopes, weights = np.concatenate(bed_slopes), np.concatenate(weights)
    descent = imp["descent_deg"]
    is_fast, is_slow = imp["speed"] > fast, imp["speed"] < slow
    alpha = float(descent[is_fast].mean()) if is_fast.any() else float("nan")
    edges = np.tan(np.radians(EDGES_DEG))
    bed_weight = np.histogram(bed_slopes, edges, weights=weights)[0]
    bed_share = bed_weight / weights.sum()

    def rate(mask):  # impacts per key point in each bin, over the mean
        if not mask.any():
            return np.full(len(edges) - 1, np.nan)
        share = np.histogram(slope_at[mask], edges)[0] / mask.sum()
        with np.errstate(invalid="ignore", divide="ignore"):
            return share / bed_share

    theory = np.full(len(edges) - 1, np.nan)
    if is_fast.any():  # the shadow rule's rate on each key point, binned and over its bed mean
        shadow = np.maximum(0.0, 1 + bed_slopes / math.tan(math.radians(alpha)))
        mean = np.sum(shadow * weights) / weights.sum()
        with np.errstate(invalid="ignore", divide="ignore"):
            theory = np.histogram(bed_slopes, edges, weights=shadow * weights)[0] / bed_weight / mean
    all_rate, fast_rate, slow_rate = rate(np.ones(len(slope_at), bool)), rate(is_fast), rate(is_slow)
    rows = []
    for q in range(len(edges) - 1):
        in_bin = is_fast & (slope_at >= edges[q]) & (slope_at < edges[q + 1])
        rows.append({
            "slope_min_deg": EDGES_DEG[q], "slope_max_deg": EDGES_DEG[q + 1], "bed_share": float(bed_share[q]),
            "rate_all": num(all_rate[q]), "rate_fast": num(fast_rate[q]), "rate_slow": num(slow_rate[q]),
            "rate_fast_shadow_rule": num(theory[q]),
            "fast_descent_deg": num(descent[in_bin].mean()) if in_bin.any() else None})
    return {"file": path, "impacts": int(len(slope_at)), "frames": int(len(used)),
            "t_star": [float(imp["t_star"].min()), float(imp["t_star"].max())], "smooth_d": smooth_d,
            "fast_speed": fast, "slow_speed": slow, "fast_share": float(is_fast.mean()),
            "slow_share": float(is_slow.mean()), "descent_deg_all": float(descent.mean()),
            "descent_deg_fast": alpha, "bins": rows}


def num(x):
    return float(x) if np.isfinite(x) else None


def show(r):
    def cell(v, fmt="{:.2f}"):
        return "-" if v is None else fmt.format(v)

    print(f"{r['file']}: {r['impacts']} impacts over t* = {r['t_star'][0]:.0f}-{r['t_star'][1]:.0f} "
          f"({r['frames']} frames); slopes along x on a {r['smooth_d']:g} d running mean")
    print(f"descent below the horizontal: {r['descent_deg_all']:.1f} deg over all impacts, "
          f"{r['descent_deg_fast']:.1f} deg over the fast ones (> {r['fast_speed']:g} cm/s, "
          f"{100 * r['fast_share']:.0f} % of impacts)\n")
    print("| slope (deg) | bed share | rate, all | fast | slow | fast, shadow rule | fast descent (deg) |")
    print("|---|---|---|---|---|---|---|")
    for b in r["bins"]:
        if b["bed_share"] < 1e-3:
            continue
        print(f"| {b['slope_min_deg']} to {b['slope_max_deg']} | {b['bed_share']:.3f} | {cell(b['rate_all'])} | "
              f"{cell(b['rate_fast'])} | {cell(b['rate_slow'])} | {cell(b['rate_fast_shadow_rule'])} | "
              f"{cell(b['fast_descent_deg'], '{:.1f}')} |")


def plot(r, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bins = [b for b in r["bins"] if b["bed_share"] >= 1e-3]
    mid = [0.5 * (b["slope_min_deg"] + b["slope_max_deg"]) for b in bins]
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for key, label, style in [("rate_fast", f"fast (> {r['fast_speed']:g} cm/s)", "o-"),
                              ("rate_slow", f"slow (< {r['slow_speed']:g} cm/s)", "s-"),
                              ("rate_fast_shadow_rule",
                               f"shadow rule, descent {r['descent_deg_fast']:.1f} deg", "k--")]:
        ax.plot(mid, [np.nan if b[key] is None else b[key] for b in bins], style, label=label)
    ax.axvline(-r["descent_deg_fast"], color="grey", lw=0.8)
    ax.set_xlabel("bed slope along the wind (deg; lee < 0 < stoss)")
    ax.set_ylabel("impacts per key point / bed mean")
    ax.set_title(f"{r['impacts']} impacts, t* {r['t_star'][0]:.0f}-{r['t_star'][1]:.0f}", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run")
    p.add_argument("--smooth", type=float, default=10.0, help="running mean along x, d (default 10)")
    p.add_argument("--fast", type=float, default=100.0, help="fast impacts: above this speed, cm/s")
    p.add_argument("--slow", type=float, default=30.0, help="slow impacts: below this speed, cm/s")
    p.add_argument("--json", action="store_true")
    p.add_argument("--plot", help="draw the rates against the slope into this PNG")
    a = p.parse_args()
    if not (a.smooth > 0 and a.fast > 0 and a.slow > 0):
        fail("--smooth, --fast and --slow must be positive")
    r = analyse(a.run, a.smooth, a.fast, a.slow)
    if a.plot:
        plot(r, a.plot)
    if a.json:
        print(json.dumps(r))
    else:
        show(r)


if __name__ == "__main__":
    main()
