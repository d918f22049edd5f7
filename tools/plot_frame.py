#!/usr/bin/python3
"""Draws one frame of a grainlab run (HDF5) as a PNG: discs as circles, polygons as outlines.

Usage: /usr/bin/python3 tools/plot_frame.py RUN.h5 [FRAME] [OUT.png]
FRAME is an index into /frames (default: the last); OUT defaults to RUN-FRAME.png.
Uses Debian's python3-h5py and python3-matplotlib.
"""
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PatchCollection  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    with h5py.File(path, "r") as f:
        names = sorted(k for k in f["frames"].keys() if k != "time")
        k = int(sys.argv[2]) if len(sys.argv) > 2 else len(names) - 1
        g = f["frames"][names[k]]
        pos, radius, angle, shape = g["position"][:], g["radius"][:], g["angle"][:], g["shape"][:]
        spin = g["spin"][:]
        time = g.attrs["time"]
        shapes = {int(n.split("_")[1]): f["shapes"][n][:] for n in f["shapes"].keys()}
        title = f.attrs["scene_name"]
        title = title.decode() if isinstance(title, bytes) else str(title)
    patches = []
    for p, r, a, s in zip(pos, radius, angle, shape):
        if s < 0:
            patches.append(Circle((p[0], p[1]), r))
        else:
            c, sn = np.cos(a), np.sin(a)
            v = shapes[int(s)] @ np.array([[c, sn], [-sn, c]]) + p[:2]
            patches.append(Polygon(v, closed=True))
    fig, ax = plt.subplots(figsize=(7, 5), dpi=110)
    coll = PatchCollection(patches, cmap="coolwarm", edgecolor="k", linewidth=0.3)
    coll.set_array(spin)
    ax.add_collection(coll)
    fig.colorbar(coll, ax=ax, label="spin (rad/s)")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_title(f"{title}, t = {time:.4g} s")
    ax.set_xlabel("x (cm)")
    ax.set_ylabel("y (cm)")
    out = sys.argv[3] if len(sys.argv) > 3 else f"{os.path.splitext(path)[0]}-{k}.png"
    fig.tight_layout()
    fig.savefig(out)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a `grainlab run` file (its /frames)")
