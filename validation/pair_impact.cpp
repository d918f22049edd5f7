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

// Positions, velocities and angular velocities (world frame; 2-D spin about z) of both grains.
struct PairState {
  Vec3 x[2], v[2], w[2];
};
PairState pair_state(const Frame& f, int dimension) {
  PairState s;
  for (int k = 0; k < 2; ++k) {
    s.x[k] = Vec3(f.position[3 * k], f.position[3 * k + 1], f.position[3 * k + 2]);
    s.v[k] = Vec3(f.velocity[3 * k], f.velocity[3 * k + 1], f.velocity[3 * k + 2]);
    s.w[k] = dimension == 3 ? Vec3(f.angular_velocity[3 * k], f.angular_velocity[3 * k + 1],
                                   f.angular_velocity[3 * k + 2])
                            : Vec3(0, 0, f.spin[k]);
  }
  return s;
}

// Normal and tangential velocity of B's contact point relative to A's, in the frame whose normal n
// points from B to A and whose tangent is z x n (the impact stays in the x-y plane).
Vec3 contact_velocity(const PairState& s, const Vec3& n) {
  const Vec3 point_b = s.v[1] + s.w[1].cross(kRadius * n), point_a = s.v[0] + s.w[0].cross(-kRadius * n);
  const Vec3 rel = point_b - point_a, t = Vec3::UnitZ().cross(n);
  return {rel.dot(n), rel.dot(t), 0};
}

}  // namespace

PairImpactResult pair_impact(const std::string& engine, int dimension, double speed, double angle_deg) {
  const double angle = angle_deg * M_PI / 180;
  // Native: 1e-7 s steps, ~700 per contact at 6e9 dyn/cm. Impulse engines: the grain moves 0.1 % of its
  // radius per step, so the line of centres at which the engine resolves the impact is the one at
  // contact to 1e-3 rad (at grazing incidence a small turn of the normal moves the normal velocity by
  // tan(angle) times as much).
  const double dt = engine_capabilities(engine).soft_contacts ? 1e-7 : 1e-3 * kRadius / speed;
  const double approach = 0.01 / speed, contact = 5 * M_PI * std::sqrt(M_PI / kStiffness);
  const Scene scene = parse_scene(pair_scene(dimension, speed, angle, dt, approach + contact + 20 * dt),
                                  "<pair impact>", {fmt::format("accuracy.dt={}", dt)});
  auto e = make_engine(engine, scene);
  const PairState before = pair_state(e->frame(), dimension);
  // The impact's frame: the line of centres at the deepest overlap. A soft contact turns while it lasts
  // (by about v_t t_contact / 2r), and the impact is measured about its middle.
  double closest = HUGE_VAL;
  Vec3 n = Vec3::UnitX();
  const int samples = 400;
  for (int k = 1; k <= samples; ++k) {
    e->advance_to(scene.duration * k / samples);
    const PairState s = pair_state(e->frame(), dimension);
    const Vec3 d = s.x[0] - s.x[1];
    if (d.norm() < closest) closest = d.norm(), n = d.normalized();
  }
  const PairState after = pair_state(e->frame(), dimension);
  const Vec3 in = contact_velocity(before, n), out = contact_velocity(after, n);
  PairImpactResult r;
  r.impact_angle_deg = std::atan2(in.y(), in.x()) * 180 / M_PI;
  r.normal_turn_deg = std::atan2(n.y(), n.x()) * 180 / M_PI;
  r.normal_restitution = -out.x() / in.x();
  r.tangential_restitution = -out.y() / in.y();
  r.rebound_angle_deg = std::atan2(out.y(), -out.x()) * 180 / M_PI;
  r.spin = after.w[1].z();
  // Both grains have density 2: mass and moment of inertia of a disc or a sphere.
  const double m = dimension == 2 ? 2 * M_PI * kRadius * kRadius : 2 * 4.0 / 3 * M_PI * std::pow(kRadius, 3);
  const double inertia = (dimension == 2 ? 0.5 : 0.4) * m * kRadius * kRadius;
  double kinetic = 0;
  for (int k = 0; k < 2; ++k)
    kinetic += 0.5 * m * after.v[k].squaredNorm() + 0.5 * inertia * after.w[k].squaredNorm();
  r.kinetic_ratio = kinetic / (0.5 * m * speed * speed);
  return r;
}

double walton_sliding_beta(double mu, double e, double inertia_factor, double angle_deg) {
  return -1 + mu * (1 + e) * (1 + 1 / inertia_factor) / std::tan(angle_deg * M_PI / 180);
}

double walton_beta(double mu, double e, double beta0, double inertia_factor, double angle_deg) {
  return std::min(beta0, walton_sliding_beta(mu, e, inertia_factor, angle_deg));
}

double rigid_spin_after(double beta, double vt, double radius, double inertia_factor) {
  return -(1 + beta) * vt / (2 * radius * (1 + inertia_factor));
}

}  // namespace grainlab::validation
