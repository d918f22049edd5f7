"""Reading `grainlab ripples hybrid --json` runs for the study tools (hybrid_wavelength_study.py,
hybrid_ensemble.py): the files of a set, a history column's mean over a window of t*, and a mean with
its standard error."""
import glob
import json
import math
import sys


def read_runs(label, patterns):
    """(path, run) for every file the globs match, in name order; exits naming the set if none does or
    a file is not a run's JSON."""
    paths = sorted({p for pat in patterns for p in glob.glob(pat)})
    if not paths:
        sys.exit(f"error: set '{label}': no file matches {' '.join(patterns)}")
    runs = []
    for p in paths:
        try:
            with open(p) as f:
                run = json.load(f)
        except (OSError, json.JSONDecodeError) as e:
            sys.exit(f"error: {p}: not a ripples hybrid --json output ({e})")
        if "history" not in run or "history_columns" not in run:
            sys.exit(f"error: {p}: no \"history\": not a ripples hybrid --json output")
        runs.append((p, run))
    return runs


def column(run, name):
    cols = run["history_columns"]
    return [r[cols.index(name)] for r in run["history"]]


def window_mean(run, name, lo, hi):
    """The mean of a history column over the frames with lo <= t* <= hi where it is defined and
    positive (nan if none)."""
    vals = [v for t, v in zip(column(run, "t_star"), column(run, name)) if lo <= t <= hi and v is not None and v > 0]
    return sum(vals) / len(vals) if vals else float("nan")


def mean_se(xs):
    """Mean, standard error of the mean (n - 1 in the variance) and count of the values that are numbers."""
    xs = [x for x in xs if x is not None and not math.isnan(x)]
    n = len(xs)
    if n == 0:
        return float("nan"), float("nan"), 0
    m = sum(xs) / n
    se = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n) if n > 1 else float("nan")
    return m, se, n
