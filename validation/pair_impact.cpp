#include "pair_impact.hpp"

#include <fmt/format.h>

#include <cmath>

#include "engine.hpp"
#include "polyhedron.hpp"

namespace grainlab::validation {

namespace {

constexpr double kRadius = 1.0, kStiffness = 6e9, kRestitution = 0.85, kMu = 0.5;

// Grain A at the origin, grain B arriving along `dir` so that the two touch, with centres on the x axis,
// after travelling 0.01 cm; both 2-D (density 2 g/cm^2) or 3-D (density 2 g/cm^3).
std::string pair_scene(int dimension, double speed, double angle, double dt, double duration) {
  const double c = std::cos(angle), s = std::sin(angle), lead = 0.01;
  const double bx = -2 * kRadius - lead * c, by = -lead * s;
  const std::string zero = dimension == 3 ? ", 0.0" : "";
  return fmt::format(R"toml(
[scene]
dimension = {dim}
name = "grain-pair impact"
duration = {duration}
gravity = [0.0, 0.0{zero}]
effects = ["normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = {dt}
[materials.grain]
k_n = {k}
restitution = {e}
k_s = {k}
mu = {mu}
[[bodies]]
radius = {r}
density = 2.0
position = [0.0, 0.0{zero}]
[[bodies]]
radius = {r}
density = 2.0
position = [{bx:.17g}, {by:.17g}{zero}]
velocity = [{vx:.17g}, {vy:.17g}{zero}]
)toml",
                     fmt::arg("dim", dimension), fmt::arg("duration", duration), fmt::arg("zero", zero),
                     fmt::arg("dt", dt), fmt::arg("k", kStiffness), fmt::arg("e", kRestitution),
                     fmt::arg("mu", kMu), fmt::arg("r", kRadius), fmt::arg("bx", bx), fmt::arg("by", by),
                     fmt::arg("vx", speed * c), fmt::arg("vy", speed * s));
}

// Velocity of grain k's surface point at its contact with the other grain (normal +x from B to A),
// relative: B's point minus A's point, as (normal, tangential) components; and B's spin.
struct ContactMotion {
  double vn = 0, vt = 0, spin_b = 0;
};
ContactMotion contact_motion(const Frame& f, int dimension) {
  // Body 0 is A (contact point at -r x), body 1 is B (contact point at +r x). Tangential: +y.
  auto vel = [&](int k, int axis) { return f.velocity[3 * k + axis]; };
  const double wa = dimension == 3 ? f.angular_velocity[3 * 0 + 2] : f.spin[0];
  const double wb = dimension == 3 ? f.angular_velocity[3 * 1 + 2] : f.spin[1];
  // Point velocity v + w z x arm: arm_A = (-r, 0) gives (0, -w r); arm_B = (r, 0) gives (0, w r).
  ContactMotion m;
  m.vn = vel(1, 0) - vel(0, 0);
  m.vt = (vel(1, 1) + wb * kRadius) - (vel(0, 1) - wa * kRadius);
  m.spin_b = wb;
  return m;
}

}  // namespace

PairImpactResult pair_impact(const std::string& engine, int dimension, double speed, double angle_deg) {
  const double angle = angle_deg * M_PI / 180;
  // Native: 1e-7 s steps, ~700 per contact at 6e9 dyn/cm; impulse engines: the grain moves 2 % of its
  // radius per step.
  const double dt = engine == "native" ? 1e-7 : 0.02 * kRadius / speed;
  const double approach = 0.01 / speed, contact = 5 * M_PI * std::sqrt(M_PI / kStiffness);
  const Scene scene = parse_scene(pair_scene(dimension, speed, angle, dt, approach + contact + 20 * dt),
                                  "<pair impact>", {fmt::format("accuracy.dt={}", dt)});
  auto e = make_engine(engine, scene);
  const ContactMotion before{speed * std::cos(angle), speed * std::sin(angle), 0};
  e->advance_to(scene.duration);
  const ContactMotion after = contact_motion(e->frame(), dimension);
  PairImpactResult r;
  r.normal_restitution = -after.vn / before.vn;
  r.tangential_restitution = -after.vt / before.vt;
  r.rebound_angle_deg = std::atan2(after.vt, -after.vn) * 180 / M_PI;
  r.spin = after.spin_b;
  return r;
}

double walton_sliding_beta(double mu, double e, double inertia_factor, double angle_deg) {
  return -1 + mu * (1 + e) * (1 + 1 / inertia_factor) / std::tan(angle_deg * M_PI / 180);
}

}  // namespace grainlab::validation
