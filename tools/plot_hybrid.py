#!/usr/bin/python3
"""Plots of a hybrid ripple run (`grainlab ripples hybrid --config F --out RUN.h5`): the bed at the last
frame (plan view), the slice-averaged profile h(x, t) as a space-time image, A(t), lambda(t), RI(t),
Q*(t) against t*, the bed's growth rate by wavelength band (positive: ripples grow there), and the mean
stoss and lee angles of the ripples' flanks against t* (runs since 2026-12-03) and the mid-air collision
rate (runs since 2026-12-04). A bed of several sizes adds the surface layer's mean grain size along the
bed beside its height at the last frame, and the mean size at crests and troughs against t*.

    /usr/bin/python3 tools/plot_hybrid.py RUN.h5 [out.png]

RUN.h5 may also be the run's checkpoint (`--checkpoint CK`), to look at a long run while it goes: the
same curves and space-time image up to its last frame, and the bed as it stands (no growth rates by band,
which the finished run computes).
"""
import re
import sys
import tomllib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def config_number(options, key, default):
    """A number of a checkpoint's config text: its [hybrid] table's, or a later --set line's."""
    value = tomllib.loads(options).get("hybrid", {}).get(key, default)
    for k, v in re.findall(r"^# --set\s+(\w+)\s*=\s*(\S+)\s*$", options, re.M):
        if k == key:
            value = v
    return float(value)


def read_run(f):
    """The history table, the key points' spacing (d), the last bed and the slice-averaged profile of every
    frame, from a run's output or from its checkpoint."""
    if text(f.attrs.get("kind", "")).startswith("grainlab-hybrid-ripples-checkpoint"):
        history = f["cli/history"]
        profiles = f["cli/profiles"][:]
        options = text(f.attrs["options"])
        # The bed at the last frame, where the run continues from: cm there, d here. (Defaults: the
        # model's, ripples/hybrid.)
        last = f["run/bed"][:] / config_number(options, "diameter", 0.025)
        return history, config_number(options, "length", 400) / profiles.shape[1], last, profiles
    names = sorted(f["frames"].keys())
    profiles = np.array([f["frames"][n][:].mean(axis=0) for n in names])
    return f["history"], float(text(f.attrs["dx"])), f["frames"][names[-1]][:], profiles


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + "_ripples.png"
    f = h5py.File(path, "r")
    history, dx, last, profiles = read_run(f)
    cols = text(history.attrs["columns"]).split(",")
    hist = history[:]
    col = {c: hist[:, i] for i, c in enumerate(cols)}
    t = col["t_star"]
    sizes = "surface_size" in f and len(f["surface_size"]) > 0  # (not in a checkpoint)
    slopes = "stoss_deg" in col
    rows = 3 + slopes + sizes
    fig = plt.figure(figsize=(13, 3 * rows))
    grid = fig.add_gridspec(rows, 5)
    ax = fig.add_subplot(grid[0, :])
    ny, nx = last.shape
    im = ax.imshow(last - last.mean(), origin="lower", cmap="terrain", aspect="auto",
                   extent=[0, nx * dx, 0, ny * dx])
    fig.colorbar(im, ax=ax, label="h - mean (d)")
    ax.set(xlabel="x (d), wind to the right", ylabel="y (d)", title=f"bed at t* = {t[-1]:.0f}")
    ax = fig.add_subplot(grid[1, :])
    dev = profiles - profiles.mean(axis=1, keepdims=True)
    im = ax.imshow(dev, origin="lower", cmap="terrain", aspect="auto", extent=[0, nx * dx, t[0], t[-1]])
    fig.colorbar(im, ax=ax, label="slice-mean h - mean (d)")
    ax.set(xlabel="x (d)", ylabel="t*", title="h(x, t), averaged across the bed (streaks leaning right: bedforms moving downwind)")
    # Beside each autocorrelation measure, the crests' own (runs since 2026-12-04): their mean spacing jumps
    # less when the crests are unevenly spaced (docs/hybrid.md, "Two measures of the wavelength").
    crest_of = {"amplitude": "crest_height", "wavelength": "crest_spacing", "ripple_index": "crest_ripple_index"}
    for k, (key, label, log) in enumerate([("amplitude", "A (d)", True), ("wavelength", "lambda (d)", True),
                                            ("ripple_index", "RI = lambda / A", True),
                                            ("mass_flux_star", "Q*", False)]):
        ax = fig.add_subplot(grid[2, k])
        keep = (col[key] > 0) & (t > 0)
        ax.plot(t[keep], col[key][keep], "o-", ms=3, label="autocorrelation" if key in crest_of else None)
        crest = col.get(crest_of.get(key, ""))
        if crest is not None and (crest > 0).any():
            keep = (crest > 0) & (t > 0)
            ax.plot(t[keep], crest[keep], "--", color="tab:green", lw=1, label="crests")
            ax.legend(fontsize="x-small", loc="upper left")
        if log and keep.any():  # (a run too short for ripples has nothing above zero to put on log axes)
            ax.set_xscale("log"), ax.set_yscale("log")
        elif not keep.any():
            ax.text(0.5, 0.5, "no ripples yet", transform=ax.transAxes, ha="center", color="gray")
        if key == "ripple_index" and keep.any():  # the paper's band over its window (Fig. 9 inset), beside the run
            ax.fill_between([5e4, 3e5], 12, 25, color="tab:orange", alpha=0.2, lw=0,
                            label="paper")
            ax.legend(fontsize="x-small", loc="lower left")
        ax.set(xlabel="t*", ylabel=label)
    if "bed_response" in f and len(f["bed_response"]) > 0:
        rcols = text(f["bed_response"].attrs["columns"]).split(",")
        r = {c: f["bed_response"][:, i] for i, c in enumerate(rcols)}
        ax = fig.add_subplot(grid[2, 4])
        mid = np.sqrt(r["lambda_min"] * r["lambda_max"])
        ax.errorbar(mid, r["growth_rate"], yerr=2 * r["growth_error"], fmt="o", ms=3)
        ax.axhline(0, color="k", lw=0.8)
        ax.set_xscale("log")
        ax.set(xlabel="wavelength (d)", ylabel="growth rate per t* (+- 2 s.e.)")
    if slopes:
        ax = fig.add_subplot(grid[3, :3])
        keep = np.isfinite(col["stoss_deg"]) & (t > 0)
        ax.plot(t[keep], col["stoss_deg"][keep], "o-", ms=3, label="stoss (rising downwind)")
        ax.plot(t[keep], col["lee_deg"][keep], "o-", ms=3, label="lee")
        ax.set(xlabel="t*", ylabel="mean flank angle (deg)",
               title="ripple flanks, slice by slice (early on: the grain-scale roughness)")
        ax.legend()
        if "collision_rate" in col and np.isfinite(col["collision_rate"]).any():  # runs since 2026-12-04
            ax = fig.add_subplot(grid[3, 3:])
            keep = np.isfinite(col["collision_rate"])
            ax.plot(t[keep], col["collision_rate"][keep], "o-", ms=3, color="tab:purple")
            ax.set(xlabel="t*", ylabel="per t* per 1,000 d^2",
                   title="mid-air collisions (they lower the ripples)")
    if sizes:
        size_rows = f["surface_size"][:]
        ax = fig.add_subplot(grid[3 + slopes, :3])
        x = np.arange(profiles.shape[1]) * dx
        ax.plot(x, profiles[-1] - profiles[-1].mean(), color="tab:brown", label="h - mean (d)")
        ax.set(xlabel="x (d)", ylabel="h - mean (d)", title=f"surface at t* = {size_rows[-1, 0]:.0f}")
        twin = ax.twinx()
        twin.plot(x, size_rows[-1, 1:], color="tab:blue", lw=0.8)
        twin.set_ylabel("mean surface grain size (d)", color="tab:blue")
        ax = fig.add_subplot(grid[3 + slopes, 3:])
        ax.plot(t, col["size_crest"], "o-", ms=3, label="crest quarter")
        ax.plot(t, col["size_trough"], "o-", ms=3, label="trough quarter")
        ax.set(xlabel="t*", ylabel="mean surface size (d)")
        ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a `ripples hybrid --out` file or checkpoint")
