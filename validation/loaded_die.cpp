#include "loaded_die.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "engine.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {
// Long enough for every throw seen to be captured (mean capture 0.3-0.5 s); Box2D sizes its length
// unit from g x duration, so a needlessly long limit would shrink the die in Box2D's units.
constexpr double kTimeLimit = 5.0;
constexpr double kDensity = 2.0, kMass = kDensity * 4.0;  // 2-D: mass per unit thickness of a 2 x 2 square
// Vertices relative to the centre of mass (counter-clockwise from (-1, -1)); face k joins k and k + 1.
std::array<Vec2, 4> body_vertices(double f) {
  return {Vec2{-1 - f, -1 - f}, Vec2{1 - f, -1 - f}, Vec2{1 - f, 1 - f}, Vec2{-1 - f, 1 - f}};
}
// The accuracy each engine runs the die at: the native contact is stiff (1e8 dyn/cm: 0.04 cm
// penetration at 150 cm/s), 45 Verlet steps per contact; the impulse engines take 1 ms steps.
std::vector<std::string> accuracy_for(const std::string& engine) {
  if (engine == "native") return {"accuracy.dt=2e-5"};
  return {"accuracy.dt=5e-4"};
}
}  // namespace

std::string die_scene_2d(const Die2d& d, double angle, double height, double vx, double spin) {
  return fmt::format(R"toml(
[scene]
name = "loaded 2-D die, f = {f}, eps = {eps}"
duration = {limit}
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.die]
k_n = 1e8
restitution = {eps}
k_s = 1e8
mu = {mu}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
center_of_mass = [{f}, {f}]
density = {rho}
position = [0.0, {h}]
angle = {angle}
velocity = [{vx}, 0.0]
spin = {spin}
)toml",
                     fmt::arg("limit", kTimeLimit), fmt::arg("f", d.f), fmt::arg("eps", d.eps), fmt::arg("mu", d.mu),
                     fmt::arg("rho", kDensity), fmt::arg("h", height), fmt::arg("angle", angle),
                     fmt::arg("vx", vx), fmt::arg("spin", spin));
}

DieThrow throw_die_2d(const std::string& engine, const Die2d& d, std::uint64_t seed, std::size_t index) {
  Rng rng(seed, index);
  const double angle = rng.uniform(0, 2 * M_PI), height = rng.uniform(3, 5), vx = rng.uniform(-50, 50),
               spin = rng.uniform(-20, 20);
  auto e = engine_for(engine, die_scene_2d(d, angle, height, vx, spin), accuracy_for(engine));
  const auto verts = body_vertices(d.f);
  const double inertia = kMass * (4.0 / 6.0 + 2 * d.f * d.f);  // square about its centre, moved to (f, f)
  const double g = kG, m = kMass;
  DieThrow out;
  // Box2D's polygons and edges each carry a skin: the die rests two skins above the plane.
  const auto diag = e->diagnostics();
  const double floor = diag.count("edge_skin_cm") ? 2 * diag.at("edge_skin_cm") : 0.0;
  for (double t = 0.01; t <= kTimeLimit + 1e-9; t += 0.01) {
    e->advance_to(t);
    const Frame fr = e->frame();
    const Vec2 c{fr.position[0], fr.position[1]}, v{fr.velocity[0], fr.velocity[1]};
    const double th = fr.angle[0], w = fr.spin[0], cs = std::cos(th), sn = std::sin(th);
    std::array<Vec2, 4> world;
    for (int k = 0; k < 4; ++k)
      world[k] = c + Vec2{cs * verts[k].x - sn * verts[k].y, sn * verts[k].x + cs * verts[k].y};
    // The face "over" which the die is: facing down, with the centre of mass above its span.
    int face = -1;
    for (int k = 0; k < 4 && face < 0; ++k) {
      const Vec2 a = world[k], b = world[(k + 1) % 4];
      if (a.x < b.x && c.x >= a.x && c.x <= b.x)
        face = k;  // counter-clockwise: a lower face runs left to right
    }
    if (face < 0) continue;
    const Vec2 a = verts[face], b = verts[(face + 1) % 4];
    const double rest = std::abs(cross(b - a, a)) / norm(b - a);  // centre of mass to the face line
    const double barrier = m * g * (std::min(norm(a), norm(b)) - rest);
    const double energy = 0.5 * m * dot(v, v) + 0.5 * inertia * w * w + m * g * (c.y - floor);
    if (energy - m * g * rest < 0.5 * barrier) {
      out.face_down = face;
      out.time = e->time();
      return out;
    }
  }
  return out;
}

}  // namespace grainlab::validation
