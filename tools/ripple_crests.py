#!/usr/bin/python3
"""Ripple crests tracked through the frames of hybrid ripple runs (`grainlab ripples hybrid --out RUN.h5`).

Why ripples merge, or do not, is a question about single crests, which the autocorrelation's A and lambda
average away. For each frame in the window this takes the span-averaged profile h(x) and finds its crests:
local maxima of a running mean over --smooth key points (5), placed between key points by a parabola, whose
prominence (the height above the higher of the two lowest points before a higher crest on either side) is at
least --prominence d. It follows each crest from frame to frame in the periodic bed (the nearest crest, between
--back d upwind and --ahead d downwind). From that:

- crests: the number of crests, a running median over 9 frames (so a crest flickering at the threshold is not
  a merger), at the window's start and end, and the mergers (the drops of that count);
- height_cv: the spread of the crests' heights (coefficient of variation), averaged over the frames;
- speed: each crest followed over --span frames gives a speed (d per t*) and a mean height H; their median,
  and the exponent beta of speed ~ H^beta (a least-squares line in log-log);
- closing_share = |beta| * height_cv: how much faster, as a share of the mean speed, a typical lower crest
  moves than a typical higher one. Mergers need such differences; a splash that slows every crest alike only
  delays them.

Usage (RUN.h5: a `ripples hybrid --out` file or the run's --checkpoint):
  python3 tools/ripple_crests.py RUN.h5 [RUN2.h5 ...] [--window T0 T1] [--json]
Several files (seeds of one setup) are also pooled: counts summed, the rest averaged over files, with the
standard error across files. Exit status 2 for a missing or unreadable file or a window with no frames.
"""
import argparse
import json
import math
import sys

import numpy as np

import hybrid_wavelengths
from hybrid_wavelengths import fail


def read_frames(path):
    """(t*, span-averaged profile) of every frame, and the key points' spacing (d), from a run's output or
    its checkpoint (hybrid_wavelengths reads both)."""
    t, _, dx, profiles = hybrid_wavelengths.read_run(path)
    return list(zip((float(x) for x in t), (np.asarray(p, dtype=float) for p in profiles))), float(dx)


def find_crests(h, dx, prominence, smooth=5):
    """Crests of a periodic profile: (x in d, prominence in d), on its running mean over `smooth` key points
    (a flat crest's highest key point wanders by several d from frame to frame; the bulk of it does not)."""
    n = len(h)
    s = hybrid_wavelengths.periodic_running_mean(h, smooth)
    out = []
    for i in range(n):
        if not (s[i] > s[i - 1] and s[i] >= s[(i + 1) % n]):
            continue
        lows = []
        for step in (1, -1):
            low, k = s[i], i
            for _ in range(n - 1):
                k = (k + step) % n
                if s[k] > s[i]:
                    break
                low = min(low, s[k])
            lows.append(low)
        p = s[i] - max(lows)
        if p >= prominence:
            # between key points: the vertex of the parabola through the maximum and its two neighbours
            a, b, c = s[i - 1], s[i], s[(i + 1) % n]
            curve = a - 2 * b + c
            shift = 0.5 * (a - c) / curve if curve < 0 else 0.0
            out.append(((i + shift) * dx % (n * dx), p))
    return out


def follow(crests, length, back, ahead, span):
    """(mean height, speed in d per frame-time unit) of crests followed over `span` frames."""
    out = []
    for a in range(len(crests) - span):
        t_a, cs_a = crests[a]
        for x0, p0 in cs_a:
            x, heights, ok = x0, [p0], True
            for b in range(a + 1, a + span + 1):
                best = None
                for y, q in crests[b][1]:
                    d = (y - x + length / 2) % length - length / 2
                    if -back <= d <= ahead and (best is None or abs(d) < abs(best[0])):
                        best = (d, y, q)
                if best is None:
                    ok = False
                    break
                x = best[1]
                heights.append(best[2])
            if ok:
                moved = (x - x0 + length / 2) % length - length / 2
                out.append((float(np.mean(heights)), moved / (crests[a + span][0] - t_a)))
    return out


def analyse(path, t0, t1, prominence, back, ahead, span, smooth=5):
    frames, dx = read_frames(path)
    frames = [(t, h) for t, h in frames if t0 <= t <= t1]
    if len(frames) < span + 2:
        fail(f"{path}: {len(frames)} frames in t* [{t0:g}, {t1:g}], need at least {span + 2}")
    length = dx * len(frames[0][1])
    crests = [(t, find_crests(h, dx, prominence, smooth)) for t, h in frames]
    counts = np.array([len(c) for _, c in crests], dtype=float)
    median = np.array([np.median(counts[max(0, i - 4):i + 5]) for i in range(len(counts))])
    cvs = [np.std([p for _, p in c]) / np.mean([p for _, p in c]) for _, c in crests if len(c) > 1]
    tracked = follow(crests, length, back, ahead, span)
    result = {
        "file": path,
        "frames": len(frames),
        "crests_start": float(median[0]),
        "crests_end": float(median[-1]),
        "mergers": int(np.sum(np.maximum(0, median[:-1] - median[1:]))),
        "height_cv": float(np.mean(cvs)) if cvs else None,
        "tracked": len(tracked),
        "speed": None,
        "beta": None,
    }
    if tracked:
        H = np.array([h for h, _ in tracked])
        c = np.array([v for _, v in tracked])
        result["speed"] = float(np.median(c))
        ok = (c > 0) & (H > 0)
        if ok.sum() >= 3 and np.ptp(np.log(H[ok])) > 0:
            result["beta"] = float(np.polyfit(np.log(H[ok]), np.log(c[ok]), 1)[0])
    if result["beta"] is not None and result["height_cv"] is not None:
        result["closing_share"] = abs(result["beta"]) * result["height_cv"]
    return result


def pooled(results):
    out = {"files": len(results), "mergers": sum(r["mergers"] for r in results)}
    for key in ("crests_start", "crests_end", "height_cv", "speed", "beta", "closing_share"):
        values = [r[key] for r in results if r.get(key) is not None]
        if values:
            out[key] = float(np.mean(values))
            out[key + "_se"] = float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else None
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--window", nargs=2, type=float, default=[0, math.inf], metavar=("T0", "T1"))
    ap.add_argument("--prominence", type=float, default=1.0, help="least crest height in d (1)")
    ap.add_argument("--back", type=float, default=2.0, help="how far upwind a crest may step per frame, d (2)")
    ap.add_argument("--ahead", type=float, default=6.0, help="how far downwind, d (6)")
    ap.add_argument("--span", type=int, default=20, help="frames a crest is followed for its speed (20)")
    ap.add_argument("--smooth", type=int, default=5, help="running mean over this many key points, odd (5)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    if a.window[1] <= a.window[0]:
        fail(f"--window {a.window[0]:g} {a.window[1]:g}: T1 must exceed T0")
    if a.prominence <= 0 or a.span < 1 or a.back < 0 or a.ahead <= 0 or a.smooth < 1 or a.smooth % 2 == 0:
        fail("--prominence and --ahead must be positive, --back not negative, --span at least 1, --smooth odd")
    results = [analyse(p, *a.window, a.prominence, a.back, a.ahead, a.span, a.smooth) for p in a.files]
    summary = {"runs": results, "pooled": pooled(results)}
    if a.json:
        print(json.dumps(summary))
        return
    for r in results + [dict(summary["pooled"], file="pooled")]:
        cells = [f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}" for k, v in r.items() if k != "file"]
        print(f"{r['file']}: " + ", ".join(cells))


if __name__ == "__main__":
    main()
