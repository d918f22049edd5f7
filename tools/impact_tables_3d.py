#!/usr/bin/env python3
"""One markdown table per case: the thesis's 2-D numbers, grainlab's discs and grainlab's spheres.

    grainlab impact --case A --dimension 3 --runs 20 --json > 3d_A.json
    grainlab impact --case A --runs 20 --json > 2d_A.json
    python3 tools/impact_tables_3d.py 3d_A.json 2d_A.json [3d_C.json 2d_C.json ...]

This is how docs/impacts.md's tables ("Impacts with spheres") are made.
"""
import json
import sys

ROWS = [
    ("eps_i", "eps_i"),
    ("eps_ix", "eps_ix"),
    ("eps_iy", "eps_iy (vertical)"),
    ("theta_i", "theta_i (deg from vertical)"),
    ("ejected", "ejected per impact"),
    ("ej_speed", "ejection speed (cm/s)"),
    ("ej_vy", "ejection vertical velocity (cm/s)"),
    ("ej_angle", "ejection angle in the incident plane (deg)"),
    ("reptation", "reptation per impact (cm)"),
    ("ej_energy", "ejected energy / incident"),
    ("eps_iz", "rebound v_y / v_i (sideways)"),
    ("ej_tilt", "ejection angle from vertical, any azimuth (deg)"),
    ("ej_sideways", "ejecta mean abs(sin azimuth)"),
    ("ej_backward", "ejecta thrown upwind (fraction)"),
]


def cell(q):
    if not isinstance(q, dict) or q.get("mean") is None:
        return "-"
    if q.get("lo") is None:  # one impact: no interval
        return f"{q['mean']:.3g}"
    return f"{q['mean']:.3g} [{q['lo']:.3g}, {q['hi']:.3g}]"


def thesis(q2, q3):
    for q, key in ((q3, "thesis_2d"), (q2, "thesis")):
        if isinstance(q, dict) and key in q:
            mean, spread = q[key]
            return f"{mean:.3g} ({spread:.2g})"
    return "-"


def table(three, two):
    head = (
        f"**CASE {three['case']}** ({three['runs']} impacts each; 3-D bed: {three['spheres']} spheres, top "
        f"{three['bed_top']:.2f} cm, packing {three['packing_fraction']:.3f}, {three['spheres_removed']} "
        f"taken away; {three['rebounds']} of {three['runs']} rebounded in 3-D, {two['rebounds']} in 2-D; "
        f"{three['median_wall_seconds']:.1f} s per impact in 3-D)\n\n"
    )
    lines = [
        "| quantity | thesis 2-D (spread) | grainlab 2-D discs | grainlab 3-D spheres |",
        "|---|---|---|---|",
    ]
    for key, label in ROWS:
        q3, q2 = three.get(key), two.get(key)
        lines.append(f"| {label} | {thesis(q2, q3)} | {cell(q2)} | {cell(q3)} |")
    return head + "\n".join(lines) + "\n"


def main(paths):
    if len(paths) < 2 or len(paths) % 2:
        sys.exit(__doc__)
    for k in range(0, len(paths), 2):
        with open(paths[k]) as f3, open(paths[k + 1]) as f2:
            print(table(json.load(f3), json.load(f2)))


if __name__ == "__main__":
    main(sys.argv[1:])
