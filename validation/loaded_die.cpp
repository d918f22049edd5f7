#include "loaded_die.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "engine.hpp"
#include "polyhedron.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {
// Long enough for every throw seen to be captured (mean capture 0.3-0.5 s); Box2D sizes its length
// unit from g x duration, so a needlessly long limit would shrink the die in Box2D's units.
constexpr double kTimeLimit = 5.0;
constexpr double kDensity = 2.0;  // g/cm^2 in 2-D, g/cm^3 in 3-D
// What the 2-D and 3-D throws share: time limit, effects, integrator and the die-plane material.
std::string die_scene_header(int dimension, double eps, double mu) {
  return fmt::format(R"toml(
[scene]
dimension = {dim}
name = "loaded {dim}-D die"
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
)toml",
                     fmt::arg("dim", dimension), fmt::arg("limit", kTimeLimit), fmt::arg("eps", eps),
                     fmt::arg("mu", mu));
}
// The accuracy each engine runs the die at: the native contact is stiff (1e8 dyn/cm: 0.04 cm
// penetration at 150 cm/s), 45 Verlet steps per contact; the impulse engines take 1 ms steps.
std::vector<std::string> accuracy_for(const std::string& engine) {
  if (engine_capabilities(engine).soft_contacts) return {"accuracy.dt=2e-5"};
  return {"accuracy.dt=5e-4"};
}
}  // namespace

std::string die_scene_2d(const Die2d& d, double angle, double height, double vx, double spin) {
  return die_scene_header(2, d.eps, d.mu) + fmt::format(R"toml(
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
                                                        fmt::arg("f", d.f), fmt::arg("rho", kDensity),
                                                        fmt::arg("h", height), fmt::arg("angle", angle),
                                                        fmt::arg("vx", vx), fmt::arg("spin", spin));
}

DieThrow throw_die_2d(const std::string& engine, const Die2d& d, std::uint64_t seed, std::size_t index,
                      const std::vector<std::string>& sets) {
  Rng rng(seed, index);
  const double angle = rng.uniform(0, 2 * M_PI), height = rng.uniform(3, 5), vx = rng.uniform(-50, 50),
               spin = rng.uniform(-20, 20);
  std::vector<std::string> all = accuracy_for(engine);
  all.insert(all.end(), sets.begin(), sets.end());
  const Scene scene = parse_scene(die_scene_2d(d, angle, height, vx, spin), "<die 2-D>", all);
  auto e = make_engine(engine, scene);
  // Mass, inertia and vertices about the centre of mass as the scene reader made them (face k joins
  // vertex k and k + 1, counter-clockwise from the (-1, -1) corner).
  const BodySpec& body = scene.bodies[0];
  const std::vector<Vec2>& verts = body.vertices;
  const double g = kG, m = body.mass, inertia = body.inertia;
  DieThrow out;
  // Box2D's polygons and edges each carry a skin: the die rests two skins above the plane.
  const auto diag = e->diagnostics();
  const double floor = diag.count("edge_skin_cm") ? 2 * diag.at("edge_skin_cm") : 0.0;
  for (double t = 0.01; t <= kTimeLimit + 1e-9; t += 0.01) {
    e->advance_to(t);
    const Frame fr = e->frame();
    const Vec2 c{fr.position[0], fr.position[1]}, v{fr.velocity[0], fr.velocity[1]};
    const double th = fr.angle[0], w = fr.spin[0], cs = std::cos(th), sn = std::sin(th);
    Vec2 world[4];
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

namespace grainlab::validation {

int die_value(double nx, double ny, double nz) {
  if (std::abs(nz) > 0.5) return nz < 0 ? 1 : 6;
  if (std::abs(ny) > 0.5) return ny < 0 ? 2 : 5;
  return nx < 0 ? 3 : 4;
}

Die3d drilled_die(double eps, double mu) {
  // Pip centres on a face, in units of the pip spacing (0.5 cm on a 2 cm die), by value.
  static const std::vector<std::vector<std::pair<int, int>>> patterns = {
      {{0, 0}},
      {{-1, -1}, {1, 1}},
      {{-1, -1}, {0, 0}, {1, 1}},
      {{-1, -1}, {-1, 1}, {1, -1}, {1, 1}},
      {{-1, -1}, {-1, 1}, {0, 0}, {1, -1}, {1, 1}},
      {{-1, -1}, {-1, 0}, {-1, 1}, {1, -1}, {1, 0}, {1, 1}}};
  const double depth = 0.06, radius = 0.15, spacing = 0.5, rho = kDensity;
  const double pip_mass = rho * M_PI * radius * radius * depth;
  const Vec3 normals[7] = {Vec3::Zero(),  Vec3(0, 0, -1), Vec3(0, -1, 0), Vec3(-1, 0, 0),
                           Vec3(1, 0, 0), Vec3(0, 1, 0),  Vec3(0, 0, 1)};
  double mass = rho * 8.0;
  Vec3 moment = Vec3::Zero();                             // first moment about the cube's centre
  Mat3 inertia = (mass * 8.0 / 12.0) * Mat3::Identity();  // uniform cube: m (2a)^2 / 6 with a = 1
  for (int v = 1; v <= 6; ++v) {
    const Vec3 n = normals[v];
    const Vec3 u = n.unitOrthogonal(), w = n.cross(u);
    for (const auto& [i, j] : patterns[v - 1]) {
      const Vec3 p = n * (1 - depth / 2) + u * (i * spacing) + w * (j * spacing);
      mass -= pip_mass;
      moment -= pip_mass * p;
      inertia -= pip_mass * (p.squaredNorm() * Mat3::Identity() - p * p.transpose());  // as point masses
    }
  }
  const Vec3 com = moment / mass;
  inertia -= mass * (com.squaredNorm() * Mat3::Identity() - com * com.transpose());  // to the centre of mass
  Die3d d;
  for (int k = 0; k < 3; ++k) d.com[k] = com[k];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d.inertia[3 * r + c] = inertia(r, c);
  d.mass = mass;
  d.eps = eps, d.mu = mu;
  return d;
}

namespace {

std::string die_scene_3d(const Die3d& d, const Quat& q, double height, const Vec3& v, const Vec3& w) {
  std::string body_mass =
      d.mass > 0 ? fmt::format("mass = {:.17g}", d.mass) : fmt::format("density = {}", kDensity);
  bool custom_inertia = false;
  for (double x : d.inertia) custom_inertia |= x != 0;
  if (custom_inertia)
    body_mass += fmt::format(
        "\ninertia = [[{:.17g}, {:.17g}, {:.17g}], [{:.17g}, {:.17g}, {:.17g}], [{:.17g}, "
        "{:.17g}, {:.17g}]]",
        d.inertia[0], d.inertia[1], d.inertia[2], d.inertia[3], d.inertia[4], d.inertia[5], d.inertia[6],
        d.inertia[7], d.inertia[8]);
  return die_scene_header(3, d.eps, d.mu) +
         fmt::format(R"toml(
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[bodies]]
shape = "box"
size = [2.0, 2.0, 2.0]
center_of_mass = [{cx:.17g}, {cy:.17g}, {cz:.17g}]
{mass}
position = [0.0, 0.0, {h:.17g}]
orientation = [{qw:.17g}, {qx:.17g}, {qy:.17g}, {qz:.17g}]
velocity = [{vx:.17g}, {vy:.17g}, 0.0]
spin = [{wx:.17g}, {wy:.17g}, {wz:.17g}]
)toml",
                     fmt::arg("cx", d.com[0]), fmt::arg("cy", d.com[1]), fmt::arg("cz", d.com[2]),
                     fmt::arg("mass", body_mass), fmt::arg("h", height), fmt::arg("qw", q.w()),
                     fmt::arg("qx", q.x()), fmt::arg("qy", q.y()), fmt::arg("qz", q.z()),
                     fmt::arg("vx", v.x()), fmt::arg("vy", v.y()), fmt::arg("wx", w.x()),
                     fmt::arg("wy", w.y()), fmt::arg("wz", w.z()));
}

// The face through which the downward vertical from the centre of mass leaves the body (body frame,
// centre of mass at the origin), or -1.
int face_below(const Polyhedron& hull, const Vec3& down) {
  int best = -1;
  double best_t = HUGE_VAL;
  for (std::size_t f = 0; f < hull.faces.size(); ++f) {
    const double c = hull.normals[f].dot(down);
    if (c <= 0) continue;
    const double t = hull.offsets[f] / c;
    if (t < best_t) best_t = t, best = static_cast<int>(f);
  }
  return best;
}

// Lowest height (above the rest height on face f) the centre of mass must pass to leave face f: over
// the nearest edge of the face.
double edge_barrier(const Polyhedron& hull, int f) {
  const auto& idx = hull.faces[f];
  double nearest = HUGE_VAL;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const Vec3 a = hull.vertices[idx[k]], b = hull.vertices[idx[(k + 1) % idx.size()]];
    nearest = std::min(nearest, a.cross(b - a).norm() / (b - a).norm());
  }
  return nearest - hull.offsets[f];
}

}  // namespace

DieThrow3d throw_die_3d(const std::string& engine, const Die3d& d, std::uint64_t seed, std::size_t index) {
  Rng rng(seed, index);
  // Uniform random rotation (Shoemake's method).
  const double u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
  const Quat q(std::sqrt(u1) * std::cos(2 * M_PI * u3), std::sqrt(1 - u1) * std::sin(2 * M_PI * u2),
               std::sqrt(1 - u1) * std::cos(2 * M_PI * u2), std::sqrt(u1) * std::sin(2 * M_PI * u3));
  const double height = rng.uniform(3, 5);
  const Vec3 v(rng.uniform(-50, 50), rng.uniform(-50, 50), 0);
  const Vec3 w(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
  const Scene scene = parse_scene(die_scene_3d(d, q, height, v, w), "<die 3-D>", accuracy_for(engine));
  auto e = make_engine(engine, scene);
  const Body3Spec& body = scene.bodies3d[0];
  const double m = body.mass, g = kG;
  DieThrow3d out;
  for (double t = 0.01; t <= kTimeLimit + 1e-9; t += 0.01) {
    e->advance_to(t);
    const Frame fr = e->frame();
    const Quat qn(fr.orientation[0], fr.orientation[1], fr.orientation[2], fr.orientation[3]);
    const Vec3 x(fr.position[0], fr.position[1], fr.position[2]),
        vel(fr.velocity[0], fr.velocity[1], fr.velocity[2]);
    const Vec3 wb =
        qn.conjugate() * Vec3(fr.angular_velocity[0], fr.angular_velocity[1], fr.angular_velocity[2]);
    const int f = face_below(body.hull, qn.conjugate() * Vec3(0, 0, -1));
    if (f < 0) continue;
    const double energy = 0.5 * m * vel.squaredNorm() + 0.5 * wb.dot(body.inertia * wb) + m * g * x.z();
    if (energy - m * g * body.hull.offsets[f] < 0.5 * m * g * edge_barrier(body.hull, f)) {
      const Vec3& n = body.hull.normals[f];
      out.value_up = 7 - die_value(n.x(), n.y(), n.z());
      out.time = e->time();
      return out;
    }
  }
  return out;
}

}  // namespace grainlab::validation
