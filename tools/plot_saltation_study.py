#!/usr/bin/python3
"""Flux against u* from `grainlab saltation study --out DIR`: one panel per planet, grainlab's mass flux for
every grain size (solid) and the classic flux laws for the middle size (dashed).

    /usr/bin/python3 tools/plot_saltation_study.py DIR [out.png]
"""
import csv
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    folder = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else folder + "/study_flux_by_planet.png"
    study = json.load(open(folder + "/study.json"))
    rows = list(csv.DictReader(open(folder + "/study.csv")))
    laws = [law["name"] for law in study["flux_laws"]]
    planets = list(dict.fromkeys(r["planet"] for r in rows))
    fig, axes = plt.subplots(1, len(planets), figsize=(5 * len(planets), 4.5), squeeze=False)
    for ax, planet in zip(axes[0], planets):
        mine = [r for r in rows if r["planet"] == planet and r["converged"] == "true"]
        sizes = sorted({float(r["diameter_cm"]) for r in mine})
        for d in sizes:
            pts = [r for r in mine if float(r["diameter_cm"]) == d]
            ax.loglog([float(r["u_star"]) for r in pts], [float(r["mass_flux"]) for r in pts], "o-",
                      label=f"grainlab, d = {d:g} cm")
        middle = sizes[len(sizes) // 2] if sizes else None
        pts = [r for r in mine if float(r["diameter_cm"]) == middle]
        for law in laws:
            ax.loglog([float(r["u_star"]) for r in pts], [float(r["Q " + law]) for r in pts], "--",
                      label=f"{law} (d = {middle:g})")
        ax.set(title=planet, xlabel="u* (cm/s)", ylabel="Q (g/(cm s))")
        ax.grid(alpha=0.3, which="both")
        # Plain numbers on the u* axis: its decade-less span gets crowded minor labels like "3x10^1" otherwise.
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xticks([t for t in (20, 30, 50, 100, 200, 300) if ax.get_xlim()[0] <= t <= ax.get_xlim()[1]])
    axes[0][-1].legend(fontsize=7, loc="center left", bbox_to_anchor=(1.02, 0.5))
    fig.tight_layout()
    fig.savefig(out, dpi=90, bbox_inches="tight")
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a `saltation study --out` folder (its study.json)")
