#include "tumbling_polygon.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "engine.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

constexpr double kDensity = 2.0;  // g/cm^2

// The contact every engine runs the polygons with: stiff native springs (0.04 cm penetration at
// 150 cm/s for a 2 x 2 cm square), 2e-5 s Verlet steps (45 per contact); 0.5 ms steps elsewhere.
std::string polygon_scene(const std::vector<Vec2>& verts, double incline_deg, double restitution, double mu,
                          double duration, Vec2 position, double angle, Vec2 velocity, double spin,
                          bool gravity = true) {
  const double th = incline_deg * M_PI / 180, g = gravity ? kG : 0.0;
  std::string vs;
  for (const Vec2& v : verts) vs += fmt::format("{}[{:.17g}, {:.17g}]", vs.empty() ? "" : ", ", v.x, v.y);
  return fmt::format(R"toml(
[scene]
name = "polygon on an incline"
duration = {duration}
gravity = [{gx:.17g}, {gy:.17g}]
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.rock]
k_n = 1e8
restitution = {e}
k_s = 1e8
mu = {mu}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [{vs}]
density = {rho}
position = [{x:.17g}, {y:.17g}]
angle = {angle:.17g}
velocity = [{vx:.17g}, {vy:.17g}]
spin = {spin:.17g}
)toml",
                     fmt::arg("duration", duration), fmt::arg("gx", g * std::sin(th)),
                     fmt::arg("gy", -g * std::cos(th)), fmt::arg("e", restitution), fmt::arg("mu", mu),
                     fmt::arg("vs", vs), fmt::arg("rho", kDensity), fmt::arg("x", position.x),
                     fmt::arg("y", position.y), fmt::arg("angle", angle), fmt::arg("vx", velocity.x),
                     fmt::arg("vy", velocity.y), fmt::arg("spin", spin));
}

std::vector<std::string> accuracy_for(const std::string& engine) {
  if (engine_capabilities(engine).soft_contacts) return {"accuracy.dt=2e-5"};
  return {"accuracy.dt=5e-4"};
}

double max_radius(const std::vector<Vec2>& verts) {
  double r = 0;
  for (const Vec2& v : verts) r = std::max(r, norm(v));
  return r;
}

// Vertices of a regular N-gon of circumradius R with one face at the bottom, horizontal.
std::vector<Vec2> regular_polygon(int n, double r) {
  std::vector<Vec2> v;
  for (int k = 0; k < n; ++k) {
    const double a = -M_PI / 2 - M_PI / n + 2 * M_PI * k / n;
    v.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return v;
}

// Centroidal moment of inertia per unit mass of a regular N-gon of circumradius R.
double regular_inertia_per_mass(int n, double r) {
  const double c = std::cos(M_PI / n);
  return r * r * (1 + 2 * c * c) / 6;
}

// An engine built for a scene, and the height at which the body's surface meets the plane there
// (Box2D's polygons and edges each carry a skin, so bodies rest two skins up).
struct Built {
  std::unique_ptr<Engine> engine;
  Scene scene;
  double floor = 0;
};
Built build(const std::string& engine, const std::string& toml, const std::vector<std::string>& sets = {}) {
  std::vector<std::string> all = accuracy_for(engine);
  all.insert(all.end(), sets.begin(), sets.end());
  Built b{nullptr, parse_scene(toml, "<tumbling polygon>", all), 0};
  b.engine = make_engine(engine, b.scene);
  const auto diag = b.engine->diagnostics();
  if (diag.count("edge_skin_cm")) b.floor = 2 * diag.at("edge_skin_cm");
  return b;
}

// A body pivoting at angular speed w about the world point p (velocity of its centroid c).
Vec2 pivot_velocity(double w, Vec2 c, Vec2 p) {
  return {-w * (c.y - p.y), w * (c.x - p.x)};
}

}  // namespace

const std::vector<TumblingShape>& tumbling_shapes() {
  static const std::vector<TumblingShape> shapes = {
      {"square", {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}},
      {"rectangle", {{-2, -1}, {2, -1}, {2, 1}, {-2, 1}}},
      // Irregular and convex; the same vertices as scenes/tumbling_hexagon.toml.
      {"hexagon", {{1.3, 0.0}, {0.6, 1.0}, {-0.5, 1.1}, {-1.4, 0.2}, {-0.8, -0.9}, {0.5, -1.1}}},
  };
  return shapes;
}

const char* motion_name(Motion m) {
  switch (m) {
    case Motion::Rest:
      return "rest";
    case Motion::Sliding:
      return "sliding";
    case Motion::Rolling:
      return "rolling";
    case Motion::Bouncing:
      return "bouncing";
  }
  return "?";
}

Motion classify(double downslope_speed, double turned, double airborne, int vertices) {
  if (turned >= 2 * M_PI / vertices) return Motion::Rolling;
  if (airborne >= 0.1) return Motion::Bouncing;
  if (std::abs(downslope_speed) < 1.0) return Motion::Rest;
  return Motion::Sliding;
}

TumbleRun tumble(const std::string& engine, const TumblingShape& s, const Incline& in, std::uint64_t seed,
                 std::size_t index) {
  Rng rng(seed, index);
  const double angle = rng.uniform(0, 2 * M_PI);
  const double size = max_radius(s.vertices);
  Built b = build(engine, polygon_scene(s.vertices, in.angle_deg, in.restitution, in.mu, kTumbleDuration,
                                        {0, 4 * size}, angle, {0, 0}, 0));
  // The scene reader moves the vertices to the centroid.
  const std::vector<Vec2>& verts = b.scene.bodies[0].vertices;
  const double touch = 0.02 * size;  // a vertex this close to the plane is touching it
  double airborne_samples = 0, samples = 0, x0 = 0, a0 = 0, v0 = 0;
  bool stopped = false;  // the acceleration is measured up to the first stop, if there is one
  TumbleRun out;
  out.acceleration = NAN;
  const double start = kTumbleDuration - kTumbleWindow;
  for (int k = 0; k <= static_cast<int>(std::lround(kTumbleWindow / 0.01)); ++k) {
    b.engine->advance_to(start + 0.01 * k);
    const Frame fr = b.engine->frame();
    const Vec2 c{fr.position[0], fr.position[1]};
    double lowest = 1e300;
    for (const Vec2& v : verts) lowest = std::min(lowest, c.y + rotate(v, fr.angle[0]).y - b.floor);
    if (k == 0) x0 = c.x, a0 = fr.angle[0], v0 = fr.velocity[0];
    airborne_samples += lowest > touch;
    samples += 1;
    out.downslope_speed = (c.x - x0) / kTumbleWindow;
    out.turned = std::abs(fr.angle[0] - a0);
    // Up to the last sample before the first stop: a slide that stops between two samples would
    // otherwise be credited with the whole interval. NaN if it stopped before the second sample.
    stopped |= std::abs(fr.velocity[0]) < 1.0;
    if (k > 0 && !stopped) out.acceleration = (fr.velocity[0] - v0) / (0.01 * k);
  }
  out.airborne = airborne_samples / samples;
  out.motion = classify(out.downslope_speed, out.turned, out.airborne, static_cast<int>(verts.size()));
  return out;
}

double pivot_ratio_rigid(int n, double e, double tilt) {
  // Pivot A and impacting vertex B span the bottom face, turned by -tilt (A up); centroid at the origin.
  const double r = 1.0, m = 1.0, inertia = m * regular_inertia_per_mass(n, r);
  const std::vector<Vec2> v = regular_polygon(n, r);
  const Vec2 a = rotate(v[0], -tilt), b = rotate(v[1], -tilt);
  const double w = -1.0;  // clockwise: rolling towards +x, B coming down
  const Vec2 vc = pivot_velocity(w, {0, 0}, a);
  const Vec2 s{-b.y, b.x};  // d(velocity of B)/d(spin)
  const Vec2 vb = vc + w * s;
  // Impulse P at B: velocity of B changes by K P with K = I/m + s s^T / I_cm; after the impact B has
  // no tangential velocity (no slip) and normal velocity -e times its approach.
  const double k11 = 1 / m + s.x * s.x / inertia, k12 = s.x * s.y / inertia,
               k22 = 1 / m + s.y * s.y / inertia;
  const Vec2 dv{-vb.x, -(1 + e) * vb.y};
  const double det = k11 * k22 - k12 * k12;
  const Vec2 p{(k22 * dv.x - k12 * dv.y) / det, (k11 * dv.y - k12 * dv.x) / det};
  const double w_after = w + cross(b, p) / inertia;
  return w_after / w;
}

double pivot_ratio_measured(const std::string& engine, int n, double restitution, double mu, double tilt,
                            const std::vector<std::string>& sets) {
  // At the impact B touches the plane and A is tilt up; the run starts 0.002 rad of pivoting about A
  // earlier (1e-4 s), in zero gravity, so nothing but B's impact changes the spin.
  const double r = std::sqrt(2.0), w = -20.0, delta = 0.002;
  const std::vector<Vec2> v = regular_polygon(n, r);
  // The engine's skin (Box2D) is read from a first build, then the scene is placed on it.
  const double floor =
      build(engine, polygon_scene(v, 0, restitution, mu, 0.02, {0, 5}, 0, {0, 0}, 0, false)).floor;
  const Vec2 b_hit{0, floor}, c_hit = b_hit - rotate(v[1], -tilt), a_hit = c_hit + rotate(v[0], -tilt);
  const Vec2 c = a_hit + rotate(c_hit - a_hit, delta);
  Built b = build(
      engine,
      polygon_scene(v, 0, restitution, mu, 0.02, c, delta - tilt, pivot_velocity(w, c, a_hit), w, false),
      sets);
  b.engine->advance_to(0.005);  // 50 contact durations after the impact; no gravity, so spin is now constant
  return b.engine->frame().spin[0] / w;
}

IdealRolling ideal_rolling(int n, double circumradius, double incline_deg, double g) {
  // Angle beta of the line pivot -> centroid from the incline's normal (downslope positive) runs from
  // -pi/N after an impact to +pi/N at the next; energy: I_P beta'^2 / 2 + m g R cos(beta + theta).
  const double th = incline_deg * M_PI / 180, R = circumradius, half = M_PI / n;
  const double ip = regular_inertia_per_mass(n, R) + R * R;  // per unit mass
  const double ratio = pivot_ratio_rigid(n, 0.0, 0.0);
  const double w_minus2 = 4 * g * R * std::sin(th) * std::sin(half) / (ip * (1 - ratio * ratio));
  const double w_plus2 = ratio * ratio * w_minus2;
  auto rate2 = [&](double beta) {
    return w_plus2 + 2 * g * R * (std::cos(-half + th) - std::cos(beta + th)) / ip;
  };
  // It must get over the top (beta = -theta) when the centroid starts behind the vertical.
  IdealRolling out;
  if (-half < -th && rate2(-th) <= 0) return out;
  // Time of one pivot, Simpson's rule (the integrand is smooth when the polygon does roll).
  const int steps = 4000;
  const double h = 2 * half / steps;
  double sum = 0;
  for (int k = 0; k <= steps; ++k) {
    const double beta = -half + k * h, weight = (k == 0 || k == steps) ? 1 : (k % 2 ? 4 : 2);
    sum += weight / std::sqrt(rate2(beta));
    // The plane must push the pivot: centripetal need below gravity's component along pivot -> centroid.
    out.lifts_off |= rate2(beta) * R > g * std::cos(beta + th);
  }
  const double period = sum * h / 3;
  out.speed = 2 * R * std::sin(half) / period;
  return out;
}

double measured_rolling_speed(const std::string& engine, int n, double circumradius, double incline_deg,
                              double restitution, double mu, double duration) {
  if (duration <= 1.0) throw std::invalid_argument("measured_rolling_speed: duration must exceed 1 s");
  const std::vector<Vec2> v = regular_polygon(n, circumradius);
  const double floor =
      build(engine, polygon_scene(v, incline_deg, restitution, mu, duration, {0, 5}, 0, {0, 0}, 0)).floor;
  // Lying on its bottom face and starting to pivot about its front vertex at the ideal steady spin.
  const double ideal = ideal_rolling(n, circumradius, incline_deg, kG).speed;
  const double w = -(ideal > 0 ? ideal / circumradius : 1.0);
  const Vec2 c{0, floor - v[0].y};
  const Vec2 front{v[1].x, floor};
  Built b = build(
      engine, polygon_scene(v, incline_deg, restitution, mu, duration, c, 0, pivot_velocity(w, c, front), w));
  b.engine->advance_to(duration - 1.0);
  const double x0 = b.engine->frame().position[0];
  b.engine->advance_to(duration);
  return b.engine->frame().position[0] - x0;
}

}  // namespace grainlab::validation
