#!/usr/bin/env python3
"""The wind's focal point as ripples grow (Huo et al. 2021, Fig. 15 and its inset) from
`grainlab ripples hybrid --json` runs at several u*.

Every frame of a ripple run carries z0, the roughness of the wind's log layer far above the grains
(history column "z0", in d). At each frame time the runs' ln z0 against 1/u* (the seeds of one u*
averaged in ln z0) give eq. 32's line, ln z0 = ln z_F - kappa u_F / u*: the focal point's height z_F and
speed u_F at that time. The paper finds u_d* (and with it u_F ~ u_d*, z_F ~ u_d*^2 / g) rising once
ripples emerge.

usage:
  tools/hybrid_focal_time.py 'runs/u*_s*.json' [--every 5000] [--plot focal_t.png] [--json]
"""
import argparse
import json
import math
import sys

from hybrid_runs import column, read_runs

KAPPA = 0.42


def line(xs, ys):
    """Least squares y = a + b x: (a, b, r^2)."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    syy = sum((y - my) ** 2 for y in ys)
    b = sxy / sxx
    return my - b * mx, b, (sxy * sxy / (sxx * syy) if syy > 0 else 1.0)


def focal_series(runs, every):
    """[(t*, z_F (d), u_F (cm/s), r^2, {u*: z0})] at the frame times every run has, every `every` t*."""
    by_time = {}
    for path, run in runs:
        if "z0" not in run["history_columns"]:
            sys.exit(f"error: {path}: its frames carry no z0 (a run from before 2026-11-28)")
        u = float(run["u_star"])
        for t, z0 in zip(column(run, "t_star"), column(run, "z0")):
            if z0 is None or not z0 > 0:
                continue
            key = round(t)
            if every > 0 and key % every:
                continue
            by_time.setdefault(key, {}).setdefault(u, []).append(math.log(z0))
    out = []
    for t in sorted(by_time):
        per_u = by_time[t]
        if len(per_u) < 2:
            continue
        us = sorted(per_u)
        ln_z0 = [sum(per_u[u]) / len(per_u[u]) for u in us]
        a, b, r2 = line([1 / u for u in us], ln_z0)
        out.append((t, math.exp(a), -b / KAPPA, r2, {u: math.exp(z) for u, z in zip(us, ln_z0)}))
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("runs", nargs="+", help="ripples hybrid --json outputs (globs), two or more u*")
    p.add_argument("--every", type=int, default=0, help="only frames at multiples of this t* (0: all)")
    p.add_argument("--plot", help="write z_F and u_F against t* to this PNG")
    p.add_argument("--json", action="store_true", help="print the series as JSON")
    a = p.parse_args()
    series = focal_series(read_runs("runs", a.runs), a.every)
    if not series:
        sys.exit("error: no frame time has z0 at two or more u*")
    if a.json:
        print(json.dumps([{"t_star": t, "z_focal_d": z, "u_focal": u, "fit_r2": r2,
                           "z0_d": {str(k): v for k, v in z0.items()}} for t, z, u, r2, z0 in series]))
    else:
        us = sorted(series[-1][4])
        print("| t* | z_F (d) | u_F (cm/s) | r^2 | " + " | ".join(f"z0 at {u:g} (d)" for u in us) + " |")
        print("|---|---|---|---|" + "---|" * len(us))
        for t, z, u, r2, z0 in series:
            cells = " | ".join(f"{z0[k]:.3g}" if k in z0 else "-" for k in us)
            print(f"| {t} | {z:.1f} | {u:.0f} | {r2:.4f} | {cells} |")
    if a.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        t = [s[0] for s in series]
        fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
        ax1.plot(t, [s[1] for s in series], "o-")
        ax1.set(ylabel="z_F (d)", title="The focal point as the ripples grow (eq. 32 at each frame)")
        ax2.plot(t, [s[2] for s in series], "o-")
        ax2.set(xlabel="t*", ylabel="u_F (cm/s)")
        for ax, k in ((ax1, 1), (ax2, 2)):
            ax.set_ylim(0, 1.2 * max(s[k] for s in series))  # from zero: a drift shows at its true size
            ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)


if __name__ == "__main__":
    main()
