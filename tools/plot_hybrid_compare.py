#!/usr/bin/env python3
"""A(t), lambda(t) and RI(t) of several `grainlab ripples hybrid --json` runs on one figure.

usage: plot_hybrid_compare.py OUT.png RUN.json[=LABEL] [RUN.json[=LABEL] ...]

Each run's JSON (the command's stdout) holds its frames' history; the paper's RI band (12-25) is shaded.
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def history(path):
    with open(path) as f:
        run = json.load(f)
    cols = run["history_columns"]
    rows = [r for r in run["history"] if r[0] > 0]
    return {c: [r[cols.index(c)] for r in rows] for c in ("t_star", "amplitude", "wavelength", "ripple_index")}


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    fig, axes = plt.subplots(3, 1, figsize=(7, 9), sharex=True)
    for arg in argv[2:]:
        path, _, label = arg.partition("=")
        h = history(path)
        for ax, key in zip(axes, ("amplitude", "wavelength", "ripple_index")):
            ax.plot(h["t_star"], h[key], label=label or path)
    axes[0].set_ylabel("A (d)")
    axes[1].set_ylabel("lambda (d)")
    axes[2].set_ylabel("RI")
    axes[2].axhspan(12, 25, color="0.85", label="paper's RI band")
    axes[2].set_xlabel("t*")
    axes[0].legend(fontsize=8)
    axes[2].legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(argv[1], dpi=110)


if __name__ == "__main__":
    main(sys.argv)
