#pragma once
// What the 3-D test scenes share: it continues a [scene] table (after dimension, duration, seed and any
// periodic sides) with the effects, velocity Verlet, a stiff sand-like material and a floor at z = 0.
inline constexpr const char* kSandSpheres3dOnAFloor =
    R"toml(effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-6
[materials.sand]
k_n = 6e9
k_s = 6e9
mu = 0.5
restitution = 0.3
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
)toml";
