#!/usr/bin/env python3
"""Writes issue #15's 3-D benchmark scene: a simple-cubic lattice of spheres (r = 1 cm, density 2.65,
spacing 2.02 cm, first centre at (1.01, 1.01, 1.01)) inside a floor and four side planes, k_n = 6e9,
Verlet dt = 1e-6 s, for STEPS steps.

    python3 tools/make_bed3d_scene.py NX NY NZ STEPS > bed3d.toml && grainlab run bed3d.toml --quiet
"""
import sys


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    nx, ny, nz, steps = (int(a) for a in sys.argv[1:])
    s = 2.02
    out = ['[scene]', 'name = "simple-cubic sphere lattice (issue #15 benchmark)"', "dimension = 3",
           f"duration = {steps * 1e-6:.9g}", 'effects = ["gravity", "normal_contact", "friction", "rotation"]',
           "[accuracy]", 'integrator = "verlet"', "dt = 1e-6",
           "[materials.sand]", "k_n = 6e9", "damping_n = 4516.0", "k_s = 6e9", "mu = 0.5"]
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                out += ["[[bodies]]", 'shape = "sphere"', "radius = 1.0", "density = 2.65",
                        f"position = [{1.01 + s * i:.6g}, {1.01 + s * j:.6g}, {1.01 + s * k:.6g}]"]
    planes = [([0, 0, 0], [0, 0, 1]), ([0, 0, 0], [1, 0, 0]), ([s * nx, 0, 0], [-1, 0, 0]),
              ([0, 0, 0], [0, 1, 0]), ([0, s * ny, 0], [0, -1, 0])]
    for point, normal in planes:
        out += ["[[walls]]", 'type = "plane"', f"point = {point}", f"normal = {normal}"]
    out += ["[output]", "frames = 2"]
    print("\n".join(out))


if __name__ == "__main__":
    main()
