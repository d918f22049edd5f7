#!/usr/bin/env python3
"""Sets of `grainlab ripples hybrid --json` runs (seeds of one set-up) compared set against set.

For each set: the mean and standard error over its runs of the final amplitude, wavelength, ripple index
(the autocorrelation's and the crests'; both also averaged over the paper's window t* = 5e4-3e5), migration speed, Q*, mid-air collisions and wall time, of the wavelength and amplitude averaged over a
window of t*, and of each wavelength band's growth rate and phase speed (the runs' "bed_response"). With
--plot, one figure: A(t), lambda(t) and RI(t) averaged over each set's runs (shaded: +- one standard
error), and the bands' growth rates against wavelength.

usage:
  tools/hybrid_ensemble.py --set "swept steps" 'runs/swept_s*.json' --set fast_substeps 'runs/fast_s*.json' \\
      [--window 20000 30000] [--plot ensemble.png] [--json]

Prints a markdown table per quantity; --json prints one JSON object instead.
"""
import argparse
import json
import math
import sys

import hybrid_runs
from hybrid_runs import column


def mean_se(values):
    """(mean, se) of the values that are numbers, None where undefined (JSON has no NaN)."""
    m, se, _ = hybrid_runs.mean_se(values)
    return (None if math.isnan(m) else m), (None if math.isnan(se) else se)


def window_mean(run, name, lo, hi):
    v = hybrid_runs.window_mean(run, name, lo, hi)
    return None if math.isnan(v) else v


def summarise(runs, window):
    scalars = {
        "amplitude": [r["amplitude"] for r in runs],
        "wavelength": [r["wavelength"] for r in runs],
        "ripple_index": [r["ripple_index"] for r in runs],
        # (Runs since 2026-12-04: the crests' own RI, and both RIs averaged over the paper's window.)
        "crest_ripple_index": [r.get("crest_ripple_index") for r in runs],
        "ripple_index_window": [r.get("ripple_index_5e4_3e5") for r in runs],
        "crest_ripple_index_window": [r.get("crest_ripple_index_5e4_3e5") for r in runs],
        "migration_speed": [r.get("migration_speed") for r in runs],
        "mass_flux_star": [r["mass_flux_star"] for r in runs],
        "collisions": [r.get("collisions") for r in runs],
        "wall_seconds": [r["wall_seconds"] for r in runs],
    }
    if window:
        lo, hi = window
        scalars["wavelength_window"] = [window_mean(r, "wavelength", lo, hi) for r in runs]
        scalars["amplitude_window"] = [window_mean(r, "amplitude", lo, hi) for r in runs]
    out = {k: dict(zip(("mean", "se"), mean_se(v))) for k, v in scalars.items()}
    bands = {}
    for r in runs:
        for b in r.get("bed_response", []):
            key = (b["lambda_min"], b["lambda_max"])
            bands.setdefault(key, []).append(b)
    out["bands"] = []
    for (lo, hi), bs in sorted(bands.items()):
        g, gse = mean_se([b["growth_rate"] for b in bs])
        p, pse = mean_se([b["phase_speed"] for b in bs])
        out["bands"].append({"lambda_min": lo, "lambda_max": hi, "runs": len(bs), "growth_rate": g,
                             "growth_se": gse, "phase_speed": p, "phase_se": pse})
    out["runs"] = len(runs)
    return out


def fmt(m, se, scale=1.0, digits=3):
    if m is None:
        return "-"
    s = f"{m * scale:.{digits}g}"
    return s if se is None else s + f" +- {se * scale:.2g}"


def print_tables(sets, window):
    rows = [("runs", "runs", 1), ("final A (d)", "amplitude", 1), ("final lambda (d)", "wavelength", 1),
            ("final RI", "ripple_index", 1), ("final RI of the crests", "crest_ripple_index", 1),
            ("mean RI, t* 5e4-3e5", "ripple_index_window", 1),
            ("mean RI of the crests, t* 5e4-3e5", "crest_ripple_index_window", 1),
            ("migration (1e-3 d per t*)", "migration_speed", 1e3),
            ("Q*", "mass_flux_star", 1), ("mid-air collisions", "collisions", 1), ("wall (s)", "wall_seconds", 1)]
    if window:
        rows[1:1] = [(f"lambda, t* {window[0]:g}-{window[1]:g} (d)", "wavelength_window", 1),
                     (f"A, t* {window[0]:g}-{window[1]:g} (d)", "amplitude_window", 1)]
    print("| | " + " | ".join(label for label, _ in sets) + " |")
    print("|---|" + "---|" * len(sets))
    for name, key, scale in rows:
        cells = []
        for _, s in sets:
            cells.append(str(s["runs"]) if key == "runs" else fmt(s[key]["mean"], s[key]["se"], scale))
        print(f"| {name} | " + " | ".join(cells) + " |")
    keys = sorted({(b["lambda_min"], b["lambda_max"]) for _, s in sets for b in s["bands"]})
    if keys:
        print("\n| band (d): growth per t* (1e-5); phase speed (1e-3 d per t*) | "
              + " | ".join(label for label, _ in sets) + " |")
        print("|---|" + "---|" * len(sets))
        for lo, hi in keys:
            cells = []
            for _, s in sets:
                b = next((b for b in s["bands"] if (b["lambda_min"], b["lambda_max"]) == (lo, hi)), None)
                cells.append("-" if b is None else fmt(b["growth_rate"], b["growth_se"], 1e5) + "; "
                             + fmt(b["phase_speed"], b["phase_se"], 1e3))
            print(f"| {lo:.0f}-{hi:.0f} | " + " | ".join(cells) + " |")


def mean_curve(runs, name):
    """A history column's mean and standard error frame by frame (the runs share their frames' times)."""
    t = column(runs[0], "t_star")
    columns = [column(r, name) for r in runs]
    n = min(len(c) for c in columns)
    means, ses = [], []
    for k in range(n):
        m, se = mean_se([c[k] for c in columns])
        means.append(m if m is not None else float("nan"))
        ses.append(se if se is not None else 0.0)
    return t[:n], means, ses


def plot(sets_runs, sets, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    panels = [("amplitude", "A (d)"), ("wavelength", "lambda (d)"), ("ripple_index", "RI")]
    for ax, (name, ylabel) in zip(axes.flat, panels):
        for (label, runs) in sets_runs:
            t, m, se = mean_curve(runs, name)
            line, = ax.plot(t, m, label=f"{label} ({len(runs)} runs)")
            ax.fill_between(t, [a - b for a, b in zip(m, se)], [a + b for a, b in zip(m, se)],
                            color=line.get_color(), alpha=0.2)
        ax.set_xlabel("t*")
        ax.set_ylabel(ylabel)
        if name == "ripple_index":
            ax.axhspan(12, 25, color="grey", alpha=0.15, label="paper's RI band")
        ax.legend(fontsize=8)
    ax = axes.flat[3]
    for label, s in sets:
        # (Bands from about 16 d up: the shortest decay tens of times faster and would flatten the rest.)
        bs = [b for b in s["bands"] if b["growth_rate"] is not None and b["lambda_min"] >= 8]
        if not bs:
            continue
        x = [math.sqrt(b["lambda_min"] * b["lambda_max"]) for b in bs]
        ax.errorbar(x, [b["growth_rate"] for b in bs], yerr=[b["growth_se"] or 0 for b in bs], marker="o",
                    capsize=3, label=label)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xscale("log")
    ax.set_xlabel("wavelength band (d, geometric centre)")
    ax.set_ylabel("growth rate per t*")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--set", nargs="+", action="append", metavar=("LABEL", "GLOB"), required=True,
                    help="a label and one or more globs of JSON files")
    ap.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"))
    ap.add_argument("--plot", metavar="PNG")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.window and not a.window[0] < a.window[1]:
        sys.exit(f"error: --window {a.window[0]:g} {a.window[1]:g}: the start must come before the end")
    sets_runs, sets = [], []
    for spec in a.set:
        if len(spec) < 2:
            sys.exit(f"error: --set {spec[0]}: give a label and at least one glob")
        runs = [run for _, run in hybrid_runs.read_runs(spec[0], spec[1:])]
        sets_runs.append((spec[0], runs))
        sets.append((spec[0], summarise(runs, a.window)))
    if a.plot:
        plot(sets_runs, sets, a.plot)
    if a.json:
        print(json.dumps({label: s for label, s in sets}))
    else:
        print_tables(sets, a.window)
        if a.plot:
            print(f"\nwrote {a.plot}")


if __name__ == "__main__":
    main()
