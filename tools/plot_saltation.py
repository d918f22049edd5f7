#!/usr/bin/python3
"""Plots runs of `grainlab saltation wind --out RUN.h5` side by side (like the thesis's Figs 4.11-4.16):
wind profiles with and without grains (log height, so the focus shows), the launch-velocity distribution,
the drag the grains take from the air, and the convergence.

    /usr/bin/python3 tools/plot_saltation.py run35.h5 run75.h5 run125.h5 --out saltation.png
"""
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import tool_errors  # noqa: E402  (tools/: drawing a file it cannot read ends in one line, status 2)


def text(attrs, key):
    v = attrs.get(key, "")
    return v.decode() if isinstance(v, bytes) else str(v)


def table(f, name):
    cols = text(f[name].attrs, "columns").split(",")
    data = f[name][:]
    return {c: data[:, i] for i, c in enumerate(cols)}


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out = "saltation.png"
    if "--out" in sys.argv:
        out = sys.argv[sys.argv.index("--out") + 1]
        args = [a for a in args if a != out]
    if not args:
        sys.exit(__doc__)
    fig, ax = plt.subplots(2, 2, figsize=(11, 8))
    for path in args:
        f = h5py.File(path, "r")
        label = f"u* {text(f.attrs, 'u_star')}: u*_eff {float(text(f.attrs, 'u_star_eff')):.1f}"
        w, l, c = table(f, "wind"), table(f, "launch"), table(f, "convergence")
        line = ax[0][0].semilogy(w["u"], w["y"], label=label)[0]
        ax[0][0].semilogy(w["u_clean"], w["y"], "--", color=line.get_color(), lw=0.8)
        ax[0][1].plot(l["v_oy"], l["F"], color=line.get_color(), label=label)
        ax[1][0].semilogy(w["drag"], w["y"], color=line.get_color(), label=label)
        ax[1][1].semilogy(c["iteration"], c["residual"], color=line.get_color(), label=label)
        splash = text(f.attrs, "splash")
    ax[0][0].set(xlabel="wind u (cm/s); dashed: without grains", ylabel="height (cm)", ylim=(1e-3, 100),
                 title="wind profiles (the focus: where they cross)")
    ax[0][1].set(xlabel="launch v_oy (cm/s)", ylabel="F (grains / cm^2 s (cm/s))", title="launch distribution")
    ax[1][0].set(xlabel="drag taken from the air (dyn/cm^3)", ylabel="height (cm)", ylim=(1e-3, 100),
                 title="grain drag profile")
    ax[1][1].set(xlabel="iteration", ylabel="largest relative change", title="convergence")
    for a in ax.flat:
        a.legend(fontsize=8)
    fig.suptitle(f"steady-state saltation, splash {splash}")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print(out)


if __name__ == "__main__":
    tool_errors.run(main, "a `saltation wind --out` file")
