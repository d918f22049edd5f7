"""`validate` stopped by a signal and continued with --resume gives the report of an uninterrupted run.

Usage: validate_resume_test.py GRAINLAB JOBS. Runs two quick suites (pair-impact, then single-body) whole
into one folder; then again into another, stopped by SIGTERM once the first suite's part is kept, and
continued with --resume. Checks that the stop left no suite process running (with --jobs 2 the suites run
in child processes, which must receive the signal too), that the continued run took the first suite from
the stopped one, and that both reports hold the same checks, the taken suite's with the same numbers.
"""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time

from stopping import stop_when

grainlab, jobs = sys.argv[1], sys.argv[2]
suites = ["--suite", "pair-impact", "--suite", "single-body", "--quick", "--jobs", jobs]


def validate(out, *extra, **popen):
    return subprocess.Popen([grainlab, "validate", *suites, "--out", out, *extra], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, **popen)


def checks(out):
    with open(os.path.join(out, "report.json")) as f:
        return json.load(f)["checks"]


def suite_processes(out):
    """The `validate --part` children still running for this folder."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):  # (read directly: procps may not be installed)
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                args = f.read().split(b"\0")
        except OSError:
            continue  # ended meanwhile
        if b"--part" in args and out.encode() in args:
            found.append(pid)
    return found


with tempfile.TemporaryDirectory() as d:
    whole, stopped = os.path.join(d, "whole"), os.path.join(d, "stopped")
    run = validate(whole)
    run.communicate(timeout=600)
    assert run.returncode in (0, 1), f"the whole run ended with {run.returncode}"
    assert not os.path.exists(os.path.join(whole, ".parts")), "the parts outlived the report"

    run = validate(stopped)
    stamp = os.path.join(stopped, ".parts", "pair-impact.stamp")
    stop_when(run, lambda: os.path.exists(stamp), "pair-impact part", 300, signal.SIGTERM)
    assert not os.path.exists(os.path.join(stopped, "report.json")), "a report from a stopped run"
    for _ in range(100):  # the children end as their own signal says
        if not suite_processes(stopped):
            break
        time.sleep(0.1)
    assert not suite_processes(stopped), f"suite processes left running: {suite_processes(stopped)}"

    run = validate(stopped, "--resume")
    _, err = run.communicate(timeout=600)
    assert run.returncode in (0, 1), f"the resumed run ended with {run.returncode}: {err}"
    assert "suite pair-impact:" in err and "taken from the interrupted run" in err, err
    assert "suite single-body:" in err and err.count("taken from the interrupted run") == 1, err
    a, b = checks(whole), checks(stopped)
    # The same checks in the same order; the suite taken from the stopped run with the same numbers (the
    # suite run again may differ in a check that times itself).
    assert [(x["id"], x["engine"]) for x in a] == [(x["id"], x["engine"]) for x in b]
    taken = [(x, y) for x, y in zip(a, b) if x["id"].startswith("pair-impact/")]
    assert len(taken) > 5 and all(x == y for x, y in taken), [x["id"] for x, y in taken if x != y]
    assert len(a) > 10, f"only {len(a)} checks"
print(f"--jobs {jobs}: stopped after pair-impact, resumed, same {len(a)} checks")
