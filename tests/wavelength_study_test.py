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

# --recorded: written-down window means join their set beside the run files, in the reading asked for, and
# the line goes through all of them; a row over another window, or for a set no --set names, is refused.
with open("recorded.csv", "w") as f:
    f.write("# a comment line\nset,u_star,seed,t_from,t_to,first_peak,spectral_peak,crest_spacing,source\n"
            "t,30,1,0,41,50,60,40,a\nt,40,1,0,41,90,100,70,b\nt,40,2,0,41,110,120,80,c\n")


def recorded(measure, window=("0", "41"), label="t", files=()):
    return subprocess.run(
        ["/usr/bin/python3", f"{tools}/hybrid_wavelength_study.py", "--ud", "20", "--window", *window,
         "--fit-below", "10", "--measure", measure, "--set", label, *files, "--recorded", "recorded.csv",
         "--json"], capture_output=True, text=True)


r = recorded("spectral_peak")
assert r.returncode == 0, r.stderr
rows = json.loads(r.stdout)["sets"][0]["rows"]
assert [(row["u_star"], row["runs"], row["recorded"], row["lambda"]) for row in rows] == [(30, 1, 1, 60), (40, 2, 2, 110)], rows
fit = json.loads(r.stdout)["sets"][0]["fit"]  # points (0.5, 60), (1, 100), (1, 120): slope 100, intercept 10
assert abs(fit["b"] - 100) < 1e-9 and abs(fit["a"] - 10) < 1e-9, fit
r = recorded("first_peak", files=(run_json,))  # the run (u* of its JSON) beside the recorded rows
assert r.returncode == 0, r.stderr
assert sum(row["runs"] for row in json.loads(r.stdout)["sets"][0]["rows"]) == 4, r.stdout
r = recorded("first_peak", window=("0", "50"))
assert r.returncode != 0 and "recorded.csv, line 3" in r.stderr and "window" in r.stderr, r.stderr
r = recorded("first_peak", label="other", files=(run_json,))
assert r.returncode != 0 and "no --set names" in r.stderr, r.stderr
print("ok")
