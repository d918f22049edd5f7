"""The impacts suite stopped part-way and continued with --resume takes up the impacts it had finished.

Usage: validate_impacts_resume_test.py GRAINLAB REFERENCE where REFERENCE is the report folder of an
uninterrupted `grainlab validate --suite impacts --quick` (ctest Validate.ImpactsQuick). Runs the same
suite into another folder, stops it by SIGTERM once CASE C's impacts are kept in its ensembles folder
(OUT/.parts/ensembles-quick-*), and continues it with --resume. The continued run must say that it took
up the interrupted run's impacts for the cases finished before the stop (and not for those after), and
its report must hold the reference's checks with the same numbers: each case's impacts, whether taken from
the file or run again, are the impacts of a run that never stopped.
"""
import glob
import json
import os
import signal
import subprocess
import sys
import tempfile

from stopping import stop_when

grainlab, reference = sys.argv[1], sys.argv[2]
args = [grainlab, "validate", "--suite", "impacts", "--quick", "--jobs", "1"]


def checks(out):
    with open(os.path.join(out, "report.json")) as f:
        return json.load(f)["checks"]


with tempfile.TemporaryDirectory() as d:
    out = os.path.join(d, "stopped")
    run = subprocess.Popen(args + ["--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    kept = os.path.join(out, ".parts", "ensembles-quick-*", "impacts-case-C.ck.h5")
    stop_when(run, lambda: glob.glob(kept), "CASE C checkpoint", 600, signal.SIGTERM)
    assert not os.path.exists(os.path.join(out, "report.json")), "a report from a stopped run"

    run = subprocess.run(args + ["--out", out, "--resume"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, timeout=900)
    assert run.returncode in (0, 1), f"the resumed run ended with {run.returncode}: {run.stderr}"
    said = [line for line in run.stderr.splitlines() if "impacts: CASE" in line]
    taken = [line.split()[2] for line in said if "continuing from the impacts of the interrupted run" in line]
    assert taken[:3] == ["A", "B", "C"], f"cases taken up: {taken}\n{run.stderr}"
    assert "I" not in taken, f"CASE I taken up, though the stop came before it: {said}"
    assert not os.path.exists(os.path.join(out, ".parts")), "the parts outlived the report"
    a, b = checks(reference), checks(out)
    assert [(x["id"], x["engine"]) for x in a] == [(x["id"], x["engine"]) for x in b], "other checks"
    differ = [x["id"] for x, y in zip(a, b) if x != y]
    assert not differ and len(a) > 10, f"checks that differ from the uninterrupted run: {differ}"
print(f"stopped after CASE C, resumed (cases taken up: {' '.join(taken)}), the same {len(a)} checks")
