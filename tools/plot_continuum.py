#!/usr/bin/python3
"""Plots of `grainlab ripples continuum --out FILE.h5`: growth rate against wavelength (the finite-difference
solver, its discrete prediction and the anti-diffusion equation's D k^2), and the steady shapes of eq. 5.8.

    /usr/bin/python3 tools/plot_continuum.py continuum.h5 [out.png]
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    path = sys.argv[1]
    out = sys.argv[2] if len(sys.argv) > 2 else path.rsplit(".", 1)[0] + ".png"
    f = h5py.File(path, "r")
    g, s = f["growth"][:], f["shapes"][:]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    ax[0].loglog(g[:, 0], g[:, 3], "-", label="continuum D k^2")
    ax[0].loglog(g[:, 0], g[:, 2], "--", label="discrete scheme")
    ax[0].loglog(g[:, 0], g[:, 1], "o", label="measured (finite differences)")
    ax[0].set(xlabel="wavelength (cm)", ylabel="growth rate (1/s)",
              title="anti-diffusion: every wave grows, the short ones fastest")
    ax[0].legend(fontsize=8)
    for col, label in ((1, "C = -0.01 cm"), (2, "flat (C = 0)"), (3, "C = +0.01 cm")):
        ax[1].plot(s[:, 0], s[:, col], label=label)
    ax[1].set(xlabel="s = x - v t (cm)", ylabel="h (cm)", title="steady shapes (eq. 5.8): flat or steepening")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a `ripples continuum --out` file")
