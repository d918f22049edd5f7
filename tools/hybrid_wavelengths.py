#!/usr/bin/python3
"""Three readings of a hybrid ripple run's wavelength, frame by frame, and the coarsening exponent chi of
each (lambda ~ t*^chi by least squares of ln lambda on ln t* over a window).

The run's own `wavelength` is the first peak of the slice-averaged autocorrelation, the paper's measure.
On a wide bed the pattern mixes waves of two lengths, and that peak can jump from one to the other in a
frame (docs/hybrid.md, "The paper's own domain"), which makes a fit over half a run say little. Beside it:
  - the peak of the power spectrum of the across-averaged profile (slice means, mean removed);
  - the mean spacing of that profile's crests: maxima of a 9-point running mean that stand more than
    --proud d above the mean.

usage: tools/hybrid_wavelengths.py RUN.h5 [--from T0] [--to T1] [--proud 0.5] [--every N] [--json]
RUN.h5: a `grainlab ripples hybrid --out` file, or the run's `--checkpoint` (which keeps every frame's
slice-averaged profile, so a run made without --out can be read too)."""
import argparse
import json
import math
import sys

import h5py
import numpy as np

import plot_hybrid


def fail(message):
    """Bad input: the message on stderr and exit status 2, as grainlab's own commands do."""
    print(f"error: {message}", file=sys.stderr)
    sys.exit(2)


def read_run(path):
    """t*, the first-peak wavelength, the key-point spacing (d) and every frame's slice-averaged profile,
    from a run's output or its checkpoint (plot_hybrid.read_run reads both)."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        fail(f"{path}: cannot be read as HDF5 ({e})")
    try:
        history, dx, _, profiles = plot_hybrid.read_run(f)
        cols = history.attrs["columns"]
        cols = (cols.decode() if isinstance(cols, bytes) else str(cols)).split(",")
        hist = history[...]
    except (KeyError, ValueError) as e:
        fail(f"{path}: not a `ripples hybrid` output or checkpoint ({e})")
    if len(profiles) != len(hist):
        fail(f"{path}: {len(profiles)} frames against {len(hist)} history rows")
    return hist[:, cols.index("t_star")], hist[:, cols.index("wavelength")], dx, profiles


def periodic_running_mean(profile, width):
    """The running mean over `width` (odd) key points of a profile periodic in x."""
    half = width // 2
    if half == 0:
        return np.asarray(profile, dtype=float)
    wrapped = np.r_[profile[len(profile) - half:], profile, profile[:half]]
    return np.convolve(wrapped, np.ones(width) / width, "valid")


def readings(profile, dx, proud):
    p = profile - profile.mean()
    nx = len(p)
    power = np.abs(np.fft.rfft(p)) ** 2
    k = int(np.argmax(power[1:])) + 1
    spectral = nx * dx / k
    smooth = periodic_running_mean(p, 9)
    crests = sum(1 for i in range(nx) if smooth[i] > smooth[i - 1] and smooth[i] >= smooth[(i + 1) % nx]
                 and smooth[i] > proud)
    return spectral, (nx * dx / crests if crests else math.nan)


def num(x):
    """A number for JSON: None for nan (too few frames to fit)."""
    return None if math.isnan(x) else x


def chi(t, lam):
    ok = [(a, b) for a, b in zip(t, lam) if a > 0 and b > 0 and not math.isnan(b)]
    if len(ok) < 3:
        return math.nan, math.nan
    x = np.log([a for a, _ in ok])
    y = np.log([b for _, b in ok])
    (slope, _), cov = np.polyfit(x, y, 1, cov=True)
    return float(slope), float(math.sqrt(cov[0][0]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--from", dest="t0", type=float, help="window start, t* (default: the run's half-way)")
    ap.add_argument("--to", dest="t1", type=float, help="window end, t* (default: the last frame)")
    ap.add_argument("--proud", type=float, default=0.5, help="a crest stands this many d above the mean")
    ap.add_argument("--every", type=int, default=1, help="print every Nth frame's row")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of the table")
    a = ap.parse_args()
    t, first_peak, dx, profiles = read_run(a.run)
    t0 = a.t0 if a.t0 is not None else t[-1] / 2
    t1 = a.t1 if a.t1 is not None else t[-1]
    if not t0 < t1:
        fail(f"--from {t0:g} must come before --to {t1:g}")
    spectral, crest = [], []
    for profile in profiles:
        s, c = readings(profile, dx, a.proud)
        spectral.append(s)
        crest.append(c)
    inside = [(t0 <= x <= t1) for x in t]
    fits = {}
    for label, lam in (("first_peak", first_peak), ("spectral_peak", spectral), ("crest_spacing", crest)):
        fits[label] = chi([x for x, i in zip(t, inside) if i], [y for y, i in zip(lam, inside) if i])
    if a.json:
        print(json.dumps({"window": [t0, t1], "t_star": list(map(float, t)),
                          "first_peak": list(map(float, first_peak)), "spectral_peak": spectral,
                          "crest_spacing": [num(c) for c in crest],
                          "chi": {k: {"value": num(v), "error": num(e)} for k, (v, e) in fits.items()}}))
        return
    print("| t* | first autocorrelation peak (d) | spectral peak (d) | crest spacing (d) |\n|---|---|---|---|")
    for k in range(0, len(t), max(1, a.every)):
        print(f"| {t[k]:.0f} | {first_peak[k]:.1f} | {spectral[k]:.1f} | {crest[k]:.1f} |")
    print(f"\nchi over t* {t0:.0f}-{t1:.0f}:")
    for k, (v, e) in fits.items():
        print(f"  {k}: {v:.3f} +- {e:.3f}")


if __name__ == "__main__":
    main()
