"""`cost` stopped by a signal and continued with --resume gives the study of an uninterrupted run.

Usage: cost_resume_test.py GRAINLAB. Studies two quick scenes (pair-restitution, then bounce-apex) whole
into one folder; then again into another, stopped by SIGTERM once the first scene is kept in the
checkpoint, and continued with --resume. Checks that the continued study took the first scene from the
checkpoint (its timings too) and measured the second, and that every row's numbers other than timings
equal the uninterrupted study's.
"""
import json
import os
import signal
import subprocess
import sys
import tempfile

from stopping import stop_when

grainlab = sys.argv[1]
args = ["cost", "--quick", "--repeats", "1", "--scene", "pair-restitution", "--scene", "bounce-apex"]


def cost(out, *extra):
    return subprocess.Popen([grainlab, *args, "--out", out, *extra], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def rows(out):
    with open(os.path.join(out, "cost.json")) as f:
        return json.load(f)


def kept_scenes(path):
    try:
        with open(path) as f:
            return set(json.load(f)["scenes"])
    except (OSError, ValueError):
        return set()


with tempfile.TemporaryDirectory() as d:
    whole, stopped = os.path.join(d, "whole"), os.path.join(d, "stopped")
    run = cost(whole)
    run.communicate(timeout=300)
    assert run.returncode == 0, f"the whole study ended with {run.returncode}"
    assert not os.path.exists(os.path.join(whole, ".cost-checkpoint.json")), "the checkpoint outlived the study"

    run = cost(stopped)
    checkpoint = os.path.join(stopped, ".cost-checkpoint.json")
    stop_when(run, lambda: "pair-restitution" in kept_scenes(checkpoint), "pair-restitution kept", 120,
              signal.SIGTERM)
    assert kept_scenes(checkpoint) == {"pair-restitution"}, kept_scenes(checkpoint)
    assert not os.path.exists(os.path.join(stopped, "cost.json")), "a study file from a stopped run"
    with open(checkpoint) as f:
        kept = json.load(f)["scenes"]["pair-restitution"]

    run = cost(stopped, "--resume")
    _, err = run.communicate(timeout=300)
    assert run.returncode == 0, f"the resumed study ended with {run.returncode}: {err}"
    assert "pair-restitution: " in err and "taken from the interrupted study" in err, err
    assert "bounce-apex: reference" in err, err
    a, b = rows(whole), rows(stopped)
    timing = ("seconds", "detail")  # (the bed's detail quotes a time per particle-step)
    strip = lambda r: {k: v for k, v in r.items() if k not in timing}
    assert [strip(r) for r in a] == [strip(r) for r in b], "the resumed study's numbers differ"
    # (The checkpoint writes NaN and infinity as strings, to read them back exactly; cost.json as null.)
    as_written = lambda r: {k: None if v in ("nan", "inf", "-inf") else v for k, v in r.items()}
    taken = [r for r in b if r["scene"] == "pair-restitution"]
    assert taken == [as_written(r) for r in kept], "the kept scene was not taken as kept"
    assert len(a) >= 6, f"only {len(a)} rows"
print(f"stopped after pair-restitution, resumed, the same {len(a)} rows")
