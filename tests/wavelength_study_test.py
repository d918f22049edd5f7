#!/usr/bin/env python3
"""tools/hybrid_wavelength_study.py --measure: each reading of a run's window is the mean of that
reading over the run's frames in the window (those where it is defined and positive), as
tools/hybrid_wavelengths.py gives them frame by frame; first_peak, the run's own, comes from its JSON and
agrees with the checkpoint's; a missing profiles file is an error naming it.

usage: wavelength_study_test.py TOOLS_DIR RUN.json RUN.ck"""
import json
import math
import subprocess
import sys

tools, run_json, run_ck = sys.argv[1:4]


def study(measure, profiles=".ck"):
    return subprocess.run(
        ["/usr/bin/python3", f"{tools}/hybrid_wavelength_study.py", "--ud", "21.3", "--window", "0", "41",
         "--measure", measure, "--profiles", profiles, "--set", "t", run_json, "--json"],
        capture_output=True, text=True)


frames = json.loads(subprocess.check_output(
    ["/usr/bin/python3", f"{tools}/hybrid_wavelengths.py", run_ck, "--from", "0", "--to", "41", "--json"]))
for measure in ("spectral_peak", "crest_spacing"):
    r = study(measure)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["measure"] == measure
    got = out["sets"][0]["rows"][0]["lambda"]
    values = [v for t, v in zip(frames["t_star"], frames[measure]) if 0 <= t <= 41 and v is not None and v > 0]
    want = sum(values) / len(values) if values else math.nan
    assert (math.isnan(got) and math.isnan(want)) or abs(got - want) <= 1e-9 * abs(want), (measure, got, want)
r = study("first_peak")
assert r.returncode == 0, r.stderr
got = json.loads(r.stdout)["sets"][0]["rows"][0]["lambda"]
values = [v for t, v in zip(frames["t_star"], frames["first_peak"]) if 0 <= t <= 41 and v > 0]
assert values and abs(got - sum(values) / len(values)) <= 1e-9 * got, (got, values)
r = study("spectral_peak", profiles=".missing.h5")
assert r.returncode != 0 and ".missing.h5" in r.stderr, r.stderr
print("ok")
