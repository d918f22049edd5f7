#!/usr/bin/python3
"""Table 4.5 (u*_eff) and CASE 1's text numbers under a reading of the thesis's unstated conventions.

Runs `grainlab saltation wind` for every cell of Table 4.5 (CASES 1-6 at their three u*) with the options
given after `--`, and prints a markdown row per case beside the thesis's values, the count of cells within
10 %, and for CASE 1 the number-density and flux peaks and the hop (the text's 0.5 cm, 3.0 cm, 3.5 / 40 cm).
docs/saltation.md ("Slow launches") was made with it.

usage:
  tools/saltation_readings.py GRAINLAB [--cases 1 5] [--tolerance 1e-4] [--json] [-- OPTIONS...]
  tools/saltation_readings.py build/release/grainlab -- --launch-min 30 --re-factor 2
"""
import argparse
import json
import subprocess
import sys

THESIS = {1: [33.1, 29.0, 24.8], 2: [25.1, 20.1, 13.9], 3: [35.0, 30.6, 24.2],
          4: [26.4, 24.6, 20.9], 5: [40.6, 35.7, 31.1], 6: [28.0, 20.4, 12.1]}
USTARS = {1: [35, 75, 125], 2: [35, 75, 125], 3: [35, 75, 125],
          4: [35, 50, 75], 5: [50, 100, 150], 6: [50, 100, 150]}


def run_cell(grainlab, case, u, tolerance, options):
    cmd = [grainlab, "saltation", "wind", "--case", str(case), "--ustar", str(u), "--json",
           "--tolerance", str(tolerance)] + options
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode == 2:  # bad options: grainlab's own message, and the same exit status
        sys.stderr.write(r.stderr)
        sys.exit(2)
    try:
        out = json.loads(r.stdout)
    except json.JSONDecodeError:
        sys.exit(f"error: {' '.join(cmd)} printed no JSON (exit {r.returncode}): {r.stderr.strip()}")
    return out if out.get("converged") else None


def main():
    args, options = sys.argv[1:], []
    if "--" in args:
        k = args.index("--")
        args, options = args[:k], args[k + 1:]
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("grainlab", help="the grainlab binary")
    p.add_argument("--cases", type=int, nargs="+", default=list(range(1, 7)), choices=range(1, 7))
    p.add_argument("--tolerance", type=float, default=1e-4)
    p.add_argument("--json", action="store_true", help="one JSON object instead of the tables")
    a = p.parse_args(args)
    cells, within, converged = {}, 0, 0
    for case in a.cases:
        for u, thesis in zip(USTARS[case], THESIS[case]):
            r = run_cell(a.grainlab, case, u, a.tolerance, options)
            cells[f"{case}@{u}"] = r
            if r:
                converged += 1
                within += abs(r["u_star_eff"] / thesis - 1) <= 0.1
    if a.json:
        print(json.dumps({"options": options, "tolerance": a.tolerance, "within_10_percent": within,
                          "converged": converged, "cells": cells}))
        return
    print(f"Table 4.5, u*_eff (cm/s), `saltation wind {' '.join(options)}` at tolerance {a.tolerance:g}\n")
    print("| CASE | u* | thesis | grainlab |\n|---|---|---|---|")
    for case in a.cases:
        got = []
        for u in USTARS[case]:
            r = cells[f"{case}@{u}"]
            got.append(f"{r['u_star_eff']:.1f}" if r else "none")
        print(f"| {case} | {', '.join(map(str, USTARS[case]))} | {', '.join(map(str, THESIS[case]))} "
              f"| {', '.join(got)} |")
    print(f"\n{within} of {converged} converged cells within 10 % of the thesis "
          f"({3 * len(a.cases) - converged} not converged)")
    if 1 in a.cases:
        print("\nCASE 1 (text: number density peaks ~0.5 cm, flux 3.0 / 3.0 / 3.4 cm, hop 3.5 / 40 cm at 35)\n")
        print("| u* | number-density peak | flux peak | energy-flux peak | drag peak | hop height / length | impact |")
        print("|---|---|---|---|---|---|---|")
        for u in USTARS[1]:
            r = cells[f"1@{u}"]
            if not r:
                print(f"| {u} | not converged | | | | | |")
                continue
            pk = r["peak_heights"]
            print(f"| {u} | {pk['number_density']:.2f} | {pk['number_flux']:.2f} | {pk['energy_flux']:.2f} "
                  f"| {pk['drag']:.2f} | {r['mean_hop_height']:.2f} / {r['mean_hop_length']:.1f} "
                  f"| ({r['impact_velocity'][0]:.0f}, {r['impact_velocity'][1]:.0f}) |")


if __name__ == "__main__":
    main()
