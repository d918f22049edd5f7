#!/usr/bin/python3
"""Draws the plots of a grainlab validation report from DIR/plots.json (written by `grainlab validate`).

Usage: /usr/bin/python3 tools/plot_report.py REPORT_DIR
Uses Debian's python3-matplotlib; PNGs are written into REPORT_DIR.
"""
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)

STYLES = {"line": dict(linestyle="-", marker=None), "dashed": dict(linestyle="--", marker=None),
          "points": dict(linestyle="none", marker="o"), "linepoints": dict(linestyle="-", marker="o")}


def draw(spec, folder):
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    if len(spec["series"]) > 10:  # the default cycle has 10 colours: keep every curve distinct
        ax.set_prop_cycle(color=plt.cm.tab20.colors)
    for s in spec["series"]:
        style = STYLES.get(s["style"], STYLES["line"])
        if s.get("err"):
            ax.errorbar(s["x"], s["y"], yerr=s["err"], label=s["label"], capsize=3, **style)
        else:
            ax.plot(s["x"], s["y"], label=s["label"], **style)
    if spec.get("logx"):
        ax.set_xscale("log")
    if spec.get("logy"):
        ax.set_yscale("log")
    ax.set_title(spec["title"])
    ax.set_xlabel(spec["xlabel"])
    ax.set_ylabel(spec["ylabel"])
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    fig.tight_layout()
    tmp = os.path.join(folder, spec["file"] + ".tmp.png")
    fig.savefig(tmp)
    os.replace(tmp, os.path.join(folder, spec["file"]))
    plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = sys.argv[1]
    with open(os.path.join(folder, "plots.json")) as f:
        for spec in json.load(f):
            draw(spec, folder)


if __name__ == "__main__":
    tool_errors.run(main, "a `validate` or `cost` report folder (its plots.json)")
