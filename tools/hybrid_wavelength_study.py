#!/usr/bin/env python3
"""The initial ripple wavelength against u* / u_d* from `grainlab ripples hybrid --json` runs.

Each run's wavelength is the mean of its frames' autocorrelation wavelengths over a window of t*; the
runs at one u* (several seeds) give a mean and its standard error. A least-squares line
lambda = a + b (u*/u_d* - 1) through the runs says whether the wavelength grows with the wind (b > 0)
and whether it vanishes at the dynamic threshold (a = 0), as Huo et al. (2021) find.

usage:
  tools/hybrid_wavelength_study.py --ud 21.3 --window 10000 20000 \\
      --set "relief fading" 'runs/fade_u*_s*.json' --set "whole relief" 'runs/whole_u*_s*.json' \\
      [--fit-below 2.5] [--plot lambda.png] [--json]

A run's u* is its JSON's "u_star"; older JSON without it is read from the .toml beside it (same stem).
Prints a markdown table per set and the fit; --json prints one JSON object instead.

--measure picks the reading of the wavelength (tools/hybrid_wavelengths.py explains the three):
first_peak (the run's own, the paper's measure; from the JSON), spectral_peak or crest_spacing (from the
frames' profiles, read from the run's checkpoint or --out file beside the JSON: same stem, the suffix
given by --profiles, `.ck` by default).

--recorded FILE.csv adds runs whose files are gone but whose window means were written down (for example
docs/data/hybrid_wavelength_2000d.csv, from docs/hybrid.md): one row per run with the columns set,
u_star, seed, t_from, t_to, first_peak, spectral_peak, crest_spacing, and optionally amplitude_end,
ripple_index_end, mass_flux_star, wall_seconds and source. A row joins the --set of its label (a --set may
then give no files); its window must be --window, so that means over other windows are not mixed in.
"""
import argparse
import csv
import json
import math
import os
import re
import sys

from hybrid_runs import mean_se, read_runs, window_mean

MEASURES = ("first_peak", "spectral_peak", "crest_spacing")


def u_star_of(path, run):
    if "u_star" in run:
        return float(run["u_star"])
    toml = os.path.splitext(path)[0] + ".toml"
    try:
        with open(toml) as f:
            m = re.search(r"^\s*u_star\s*=\s*([0-9.eE+-]+)", f.read(), re.M)
    except OSError:
        m = None
    if not m:
        sys.exit(f"error: {path}: no \"u_star\" in the JSON and none in {toml}")
    return float(m.group(1))


def run_wavelength(path, run, args):
    """The run's wavelength over the window, in the reading --measure asks for."""
    if args.measure == "first_peak":
        return window_mean(run, "wavelength", *args.window)
    import hybrid_wavelengths  # (h5py and numpy: only needed for these readings)

    profiles_file = os.path.splitext(path)[0] + args.profiles
    if not os.path.exists(profiles_file):
        sys.exit(f"error: {path}: --measure {args.measure} reads the frames' profiles, and {profiles_file} "
                 "does not exist (--profiles gives its suffix)")
    t, _, dx, profiles = hybrid_wavelengths.read_run(profiles_file)
    values = []
    for ti, profile in zip(t, profiles):
        if args.window[0] <= ti <= args.window[1]:
            spectral, crest = hybrid_wavelengths.readings(profile, dx, 0.5)
            value = spectral if args.measure == "spectral_peak" else crest
            if not math.isnan(value) and value > 0:  # (as window_mean takes the run's own)
                values.append(value)
    return sum(values) / len(values) if values else math.nan


def fit_line(points):
    """Ordinary least squares y = a + b x; returns a, b and their standard errors."""
    n = len(points)
    if n < 3:
        return None
    mx = sum(x for x, _ in points) / n
    my = sum(y for _, y in points) / n
    sxx = sum((x - mx) ** 2 for x, _ in points)
    if sxx <= 1e-12 * max(1.0, mx * mx):  # one u* only: no line to fit
        return None
    b = sum((x - mx) * (y - my) for x, y in points) / sxx
    a = my - b * mx
    s2 = sum((y - a - b * x) ** 2 for x, y in points) / (n - 2)
    return {"a": a, "b": b, "a_se": math.sqrt(s2 * (1 / n + mx * mx / sxx)), "b_se": math.sqrt(s2 / sxx)}


RECORDED_COLUMNS = ("set", "u_star", "seed", "t_from", "t_to") + MEASURES
RECORDED_OPTIONAL = ("amplitude_end", "ripple_index_end", "mass_flux_star", "wall_seconds")


def read_recorded(path, window):
    """Rows of a --recorded CSV as {label: [run entries]}; exits naming the file and line on bad input."""
    def number(row, key, where, optional=False):
        text = (row.get(key) or "").strip()
        if not text and optional:
            return math.nan
        try:
            return float(text)
        except ValueError:
            sys.exit(f"error: {where}: column {key} is {text!r}, not a number")

    try:
        with open(path, newline="") as f:
            numbered = [(n, line) for n, line in enumerate(f, start=1) if line.strip() and not line.startswith("#")]
    except OSError as e:
        sys.exit(f"error: --recorded {path}: {e.strerror}")
    reader = csv.DictReader([line for _, line in numbered])
    missing = [c for c in RECORDED_COLUMNS if c not in (reader.fieldnames or [])]
    if missing:
        sys.exit(f"error: --recorded {path}: no column {', '.join(missing)}")
    by_label = {}
    for (n, _), row in zip(numbered[1:], reader):  # (one line per row: the file has no quoted line breaks)
        where = f"{path}, line {n}"
        t_from, t_to = number(row, "t_from", where), number(row, "t_to", where)
        if [t_from, t_to] != list(window):
            sys.exit(f"error: {where}: window t* {t_from:g}-{t_to:g}, not the --window {window[0]:g}-{window[1]:g}")
        entry = {"file": f"{row.get('source') or path} (seed {row['seed']})", "recorded": True,
                 "u_star": number(row, "u_star", where), "t_star": t_to, "migration_speed": math.nan}
        entry.update({m: number(row, m, where) for m in MEASURES})
        entry.update({c: number(row, c, where, optional=True) for c in RECORDED_OPTIONAL})
        entry["amplitude"], entry["ripple_index"] = entry.pop("amplitude_end"), entry.pop("ripple_index_end")
        by_label.setdefault(row["set"], []).append(entry)
    return by_label


def load_set(label, patterns, args, recorded=()):
    by_u = {}
    for r in recorded:
        by_u.setdefault(r["u_star"], []).append(dict(r, **{"lambda": r[args.measure]}))
    for f, run in read_runs(label, patterns) if patterns else []:  # (main: files, recorded rows or both)
        if run["t_star"] < args.window[1]:
            print(f"warning: {f} ends at t* {run['t_star']:.0f}, inside the window", file=sys.stderr)
        u = u_star_of(f, run)
        by_u.setdefault(u, []).append(
            {
                "file": f,
                "lambda": run_wavelength(f, run, args),
                "amplitude": run["amplitude"],
                "ripple_index": run["ripple_index"],
                "migration_speed": run["migration_speed"],
                "mass_flux_star": run["mass_flux_star"],
                "wall_seconds": run["wall_seconds"],
                "t_star": run["t_star"],
            }
        )
    rows, points = [], []
    for u in sorted(by_u):
        runs = by_u[u]
        lam, lam_se, n = mean_se([r["lambda"] for r in runs])
        x = u / args.ud
        if x <= args.fit_below:
            points += [(x - 1, r["lambda"]) for r in runs if not math.isnan(r["lambda"])]
        rows.append(
            {
                "u_star": u,
                "u_ratio": x,
                "runs": n,
                "recorded": sum(r.get("recorded", False) for r in runs),
                "lambda": lam,
                "lambda_se": lam_se,
                "lambda_runs": [r["lambda"] for r in runs],
                "amplitude_end": mean_se([r["amplitude"] for r in runs])[0],
                "ripple_index_end": mean_se([r["ripple_index"] for r in runs])[0],
                "migration_speed": mean_se([r["migration_speed"] or float("nan") for r in runs])[0],
                "mass_flux_star": mean_se([r["mass_flux_star"] for r in runs])[0],
                "wall_seconds": mean_se([r["wall_seconds"] for r in runs])[0],
                "t_end": min(r["t_star"] for r in runs),
            }
        )
    return {"label": label, "rows": rows, "fit": fit_line(points), "fit_points": len(points)}


def shown(value, spec):
    """A table cell: the number, or '-' where no run gave one (recorded runs may lack it)."""
    return "-" if value is None or math.isnan(value) else format(value, spec)


def print_markdown(s, args):
    lo, hi = args.window
    print(f"\n{s['label']} ({args.measure} averaged over t* {lo:.0f}-{hi:.0f}; u_d* = {args.ud} cm/s)\n")
    print("| u* (cm/s) | u*/u_d* | runs | lambda (d) | A at the end (d) | RI at the end | migration (d per t*) | Q* | wall per run (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in s["rows"]:
        runs = f"{r['runs']} ({r['recorded']} recorded)" if r["recorded"] else f"{r['runs']}"
        print(
            f"| {r['u_star']:g} | {r['u_ratio']:.2f} | {runs} | {r['lambda']:.0f} +- {r['lambda_se']:.0f} "
            f"| {shown(r['amplitude_end'], '.2f')} | {shown(r['ripple_index_end'], '.1f')} "
            f"| {shown(r['migration_speed'], '.2g')} | {shown(r['mass_flux_star'], '.4f')} "
            f"| {shown(r['wall_seconds'], '.0f')} |"
        )
    f = s["fit"]
    if f:
        print(
            f"\nfit over {s['fit_points']} runs (u*/u_d* <= {args.fit_below}): lambda = ({f['a']:.1f} +- {f['a_se']:.1f}) d"
            f" + ({f['b']:.1f} +- {f['b_se']:.1f}) d x (u*/u_d* - 1)"
        )
    else:
        print(f"\nno fit: a line needs at least 3 runs at two or more u* (u*/u_d* <= {args.fit_below})")


def plot(sets, args):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4.2))
    for s, mark in zip(sets, "osd^v"):
        xs = [r["u_ratio"] for r in s["rows"]]
        line = ax.errorbar(xs, [r["lambda"] for r in s["rows"]], yerr=[r["lambda_se"] for r in s["rows"]],
                           fmt=mark, capsize=3, label=s["label"])
        for r in s["rows"]:  # each run, faint, so the spread between seeds shows
            ax.plot([r["u_ratio"]] * len(r["lambda_runs"]), r["lambda_runs"], mark, ms=3, alpha=0.35,
                    color=line[0].get_color())
        f = s["fit"]
        if f:
            xx = [1, max(xs)]
            ax.plot(xx, [f["a"] + f["b"] * (x - 1) for x in xx], "--", color=line[0].get_color(), lw=1)
    ax.set_xlabel("u* / u_d*")
    ax.set_ylabel(f"lambda (d, {args.measure.replace('_', ' ')}), t* {args.window[0]:.0f}-{args.window[1]:.0f}")
    ax.set_xlim(left=0.9)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    tmp = args.plot + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, args.plot)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--ud", type=float, required=True, help="the dynamic threshold u_d* (cm/s)")
    p.add_argument("--window", type=float, nargs=2, default=[10000, 20000], metavar=("T0", "T1"))
    p.add_argument("--set", nargs="+", action="append", required=True, metavar=("LABEL", "GLOB"),
                   help="a label and the run JSON files (globs) of one set")
    p.add_argument("--fit-below", type=float, default=2.5, help="fit only runs with u*/u_d* up to this")
    p.add_argument("--measure", choices=MEASURES, default="first_peak",
                   help="the reading of the wavelength (default: first_peak, the run's own)")
    p.add_argument("--profiles", default=".ck",
                   help="suffix of the file beside each JSON that holds the frames' profiles (default .ck)")
    p.add_argument("--recorded", metavar="CSV", help="window means of runs whose files are gone (see above)")
    p.add_argument("--plot", help="write lambda against u*/u_d* to this PNG")
    p.add_argument("--json", action="store_true")
    args = p.parse_args()
    if args.ud <= 0 or args.window[1] <= args.window[0]:
        p.error("need --ud > 0 and a window T0 < T1")
    recorded = read_recorded(args.recorded, args.window) if args.recorded else {}
    for s in args.set:
        if len(s) < 2 and s[0] not in recorded:
            p.error(f"--set {s[0]}: give a label and at least one file (or rows of --recorded)")
    unknown = sorted(set(recorded) - {s[0] for s in args.set})
    if unknown:
        p.error(f"--recorded: rows for set {', '.join(unknown)}, which no --set names")
    sets = [load_set(s[0], s[1:], args, recorded.get(s[0], [])) for s in args.set]
    if args.plot:
        plot(sets, args)
    if args.json:
        print(json.dumps({"u_d_star": args.ud, "window": args.window, "measure": args.measure, "sets": sets}))
    else:
        for s in sets:
            print_markdown(s, args)


if __name__ == "__main__":
    main()
