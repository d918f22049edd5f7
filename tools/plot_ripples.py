#!/usr/bin/python3
"""Space-time plot of a ripple run (`grainlab ripples bins|lattice --out RUN.h5`): the surface h(x, t) as an
image (time up), with the roughness and wavelength beside it, and the final profile.

    /usr/bin/python3 tools/plot_ripples.py RUN.h5 [out.png]
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def text_columns(dataset):
    v = dataset.attrs["columns"]
    return (v.decode() if isinstance(v, bytes) else str(v)).split(",")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + "_spacetime.png"
    f = h5py.File(path, "r")
    h = f["h"][:]
    hist = f["history"][:]
    model = f.attrs.get("model", b"")
    model = model.decode() if isinstance(model, bytes) else str(model)
    lattice = "lattice" in model
    generic = "dx" in f.attrs  # `grainlab ripples run`: heights and x already in grain diameters
    if generic:
        def text(key):
            v = f.attrs[key]
            return v.decode() if isinstance(v, bytes) else str(v)
        cols = text_columns(f["history"])
        dx = float(text("dx"))
        width, xlabel, tlabel = h.shape[1] * dx, "x (grain diameters)", text("time_unit")
        hist = hist[:, [0, cols.index("rms"), cols.index("wavelength")]]
        wl_label, wl_scale, lattice = "wavelength (grain diameters)", 1.0, False
    elif lattice:
        # One value per lattice spacing (the mean of its two columns, removing the lattice's zig-zag), in
        # grain diameters (a layer is d / 2); x in grain diameters (a spacing is sqrt(3) d).
        n = h.shape[1] // 2 * 2
        h = 0.25 * (h[:, 0:n:2] + h[:, 1:n:2])
        width, xlabel, tlabel = h.shape[1] * np.sqrt(3), "x (grain diameters)", "ejections per surface grain"
        wl_label, wl_scale = "wavelength (grain diameters)", np.sqrt(3)
    else:
        width, xlabel, tlabel = h.shape[1], "x (bins)", "shots fired"
        wl_label, wl_scale = "dominant wavelength (bins)", 1.0
    fig, ax = plt.subplots(2, 2, figsize=(12, 7), gridspec_kw={"width_ratios": [3, 1], "height_ratios": [3, 1]})
    dev = h - h.mean(axis=1, keepdims=True)
    im = ax[0][0].imshow(dev, aspect="auto", origin="lower", cmap="terrain",
                         extent=[0, width, hist[0, 0], hist[-1, 0]])
    fig.colorbar(im, ax=ax[0][0], label="height - mean (grain diameters)")
    ax[0][0].set(xlabel=xlabel, ylabel=tlabel, title="h(x, t): ripples form, migrate and merge")
    ax[0][1].plot(hist[:, 0], hist[:, 2] * wl_scale, label=wl_label)
    ax[0][1].plot(hist[:, 0], hist[:, 1] * (0.5 if lattice else 1.0), label="rms roughness (d)")
    ax[0][1].set(xlabel=tlabel, title="coarsening")
    ax[0][1].legend(fontsize=8)
    x = np.linspace(0, width, h.shape[1], endpoint=False)
    part = max(8, h.shape[1] // 6)  # a stretch of the final surface, true to scale
    ax[1][0].plot(x[:part], dev[-1][:part], lw=0.8)
    ax[1][0].set(xlabel=xlabel, ylabel="h (d)", title="final surface, true scale (wind from the left)")
    ax[1][0].set_aspect("equal")
    ax[1][1].axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a ripple model's `--out` file (its h(x, t))")
