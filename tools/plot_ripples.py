#!/usr/bin/python3
"""Space-time plot of a ripple run (`grainlab ripples bins --out RUN.h5`): the surface h(x, t) as an image
(time up), with the roughness and dominant wavelength beside it.

    /usr/bin/python3 tools/plot_ripples.py bins.h5 [out.png]
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + "_spacetime.png"
    f = h5py.File(path, "r")
    h = f["h"][:]
    hist = f["history"][:]
    fig, ax = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [3, 1]})
    dev = h - h.mean(axis=1, keepdims=True)
    im = ax[0].imshow(dev, aspect="auto", origin="lower", cmap="terrain",
                      extent=[0, h.shape[1], hist[0, 0], hist[-1, 0]])
    fig.colorbar(im, ax=ax[0], label="height - mean (grain diameters)")
    ax[0].set(xlabel="x (bins)", ylabel="shots fired", title="h(x, t): ripples form, migrate and merge")
    ax[1].plot(hist[:, 0], hist[:, 2], label="dominant wavelength (bins)")
    ax[1].plot(hist[:, 0], hist[:, 1], label="rms roughness (d)")
    ax[1].set(xlabel="shots fired", title="coarsening")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    main()
