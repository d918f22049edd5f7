#!/usr/bin/env python3
"""Writes the bench's simple-cubic sphere lattice (issue #15: r = 1 cm, density 2.65, spacing 2.02 cm,
k_n = k_s = 6e9 dyn/cm, in a box of five planes) as a scene already at rest under its own weight.

Each layer is pressed into the one below (or the floor) by the weight of the spheres it carries, so the
first step finds every vertical contact at its equilibrium depth and nothing moves. That is the settled
variant of `grainlab bench bed3d` without its 50,000 settling steps, for timing large beds:

    python3 bench/lattice_at_rest.py 100 100 10 rest100k.toml
    grainlab bench bed3d --bed-scene rest100k.toml --steps 2000

The contacts are linear springs (gran/hooke), so layer k from the top carries k sphere weights and sinks
m g / k_n per weight carried into the layer below.
"""
import argparse
import math
import os
import sys
import tempfile

SPACING = 2.02  # cm, centre to centre along x and y
RADIUS = 1.0  # cm
DENSITY = 2.65  # g/cm^3
K_N = 6e9  # dyn/cm
G = 981.0  # cm/s^2


def heights(nz):
    """Centre heights of the nz layers, bottom first, each pressed by the weight above it."""
    sink = DENSITY * 4 / 3 * math.pi * RADIUS**3 * G / K_N  # one sphere's weight on one contact
    z = [RADIUS - nz * sink]  # the bottom layer carries all nz weights on the floor
    for k in range(nz - 1):
        z.append(z[-1] + 2 * RADIUS - (nz - 1 - k) * sink)
    return z


def scene_text(nx, ny, nz):
    out = [
        "[scene]",
        f'name = "bench bed3d {nx} x {ny} x {nz}, lattice at rest under its weight"',
        "dimension = 3",
        "duration = 1.0",
        "seed = 1",
        'effects = ["gravity", "normal_contact", "friction", "rotation"]',
        "[accuracy]",
        'integrator = "verlet"',
        "dt = 1e-6",
        "[materials.grain]",
        "k_n = 6e9",
        "gamma_n = 4516",
        "k_s = 6e9",
        "gamma_s = 2258",
        "mu = 0.5",
    ]
    zs = heights(nz)
    for i in range(nx):
        for j in range(ny):
            for z in zs:
                out += [
                    "[[bodies]]",
                    'shape = "sphere"',
                    f"radius = {RADIUS!r}",
                    f"density = {DENSITY!r}",
                    f"position = [{1.01 + SPACING * i!r}, {1.01 + SPACING * j!r}, {z!r}]",
                ]
    width, depth = SPACING * nx, SPACING * ny
    for point, normal in (([0, 0, 0], [0, 0, 1]), ([0, 0, 0], [1, 0, 0]), ([width, 0, 0], [-1, 0, 0]),
                          ([0, 0, 0], [0, 1, 0]), ([0, depth, 0], [0, -1, 0])):
        out += ["[[walls]]", 'type = "plane"', f"point = {point!r}", f"normal = {normal!r}"]
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("nx", type=int)
    ap.add_argument("ny", type=int)
    ap.add_argument("nz", type=int)
    ap.add_argument("out", help="the scene file to write (TOML)")
    a = ap.parse_args()
    for name in ("nx", "ny", "nz"):
        if getattr(a, name) < 1:
            print(f"lattice_at_rest.py: {name} must be at least 1, not {getattr(a, name)}", file=sys.stderr)
            return 2
    # Written beside the target and renamed: no half-written scene is ever left under its name.
    folder = os.path.dirname(os.path.abspath(a.out))
    with tempfile.NamedTemporaryFile("w", dir=folder, delete=False, suffix=".tmp") as f:
        f.write(scene_text(a.nx, a.ny, a.nz))
    os.replace(f.name, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
