#!/usr/bin/python3
"""Draws a grainlab-splash/1 file: for each incident cell, the ejecta's launch velocities (v_x, v_y) as a heat
map (ejecta per impact per bin, in units of sqrt(g d)), with the mean rebound velocity marked.

    /usr/bin/python3 tools/plot_splash.py splash.h5 [out.png]
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + "_splash.png"
    f = h5py.File(path, "r")
    schema = f.attrs["schema"]
    schema = schema.decode() if isinstance(schema, bytes) else schema
    if schema != "grainlab-splash/1":
        sys.exit(f"{path}: schema {schema!r}, expected 'grainlab-splash/1'")
    cells = [f["cells"][k] for k in sorted(f["cells"])]
    speeds = sorted({round(float(c.attrs["speed"]), 6) for c in cells})
    angles = sorted({round(float(c.attrs["angle"]), 6) for c in cells})
    fig, axes = plt.subplots(len(speeds), len(angles), figsize=(3 * len(angles), 2.6 * len(speeds)),
                             squeeze=False, sharex=True, sharey=True)
    for ax in axes.flat:
        ax.set_visible(False)
    vmax_all = max((np.abs(c["ejecta"][:, 3:5]).max() for c in cells if c["ejecta"].shape[0]), default=1.0)
    lim = min(vmax_all, 15.0)
    bins = np.linspace(-lim, lim, 31)
    for c in cells:
        i = speeds.index(round(float(c.attrs["speed"]), 6))
        j = angles.index(round(float(c.attrs["angle"]), 6))
        ax = axes[i][j]
        ax.set_visible(True)
        e = c["ejecta"][:]
        n = max(1, int(c.attrs["impacts"]))
        if e.shape[0]:
            h, xe, ye = np.histogram2d(e[:, 3], e[:, 4], bins=[bins, bins])
            ax.pcolormesh(xe, ye, (h / n).T, cmap="viridis", shading="flat")
        r = c["rebound"][:]
        if r.shape[0] and r[:, 1].sum() > 0:
            up = r[r[:, 1] > 0]
            ax.plot(up[:, 2].mean(), up[:, 3].mean(), "r^", ms=6)
        ax.set_title(f"v={c.attrs['speed']:.3g}, {c.attrs['angle']:.0f} deg: {e.shape[0] / n:.1f} ej/impact",
                     fontsize=8)
        ax.set_xlim(-lim, lim)
        ax.set_ylim(0, lim)
    for ax in axes[-1]:
        ax.set_xlabel("launch v_x / sqrt(g d)")
    for row in axes:
        row[0].set_ylabel("launch v_y / sqrt(g d)")
    title = f.attrs.get("title", "")
    title = title.decode() if isinstance(title, bytes) else title
    fig.suptitle(f"{title}\n(ejecta per impact per bin; red: mean rebound, often off the axes)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a grainlab-splash/1 file")
