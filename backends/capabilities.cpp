#include <fmt/format.h>

#include <algorithm>

#include "contact_law.hpp"
#include "engine.hpp"
#include "world.hpp"
#include "world3d.hpp"

namespace grainlab {

std::unique_ptr<Engine> make_native_engine(const Scene& scene);
std::unique_ptr<Engine> make_box2d_engine(const Scene& scene, std::vector<BodySpec> bodies);
std::unique_ptr<Engine> make_ode_engine(const Scene& scene, std::vector<BodySpec> bodies);
std::unique_ptr<Engine> make_bullet_engine(const Scene& scene, std::vector<BodySpec> bodies);

namespace {
// The rigid-body engines get the scene's bodies with its generated beds already built (by the native
// engine's own pour, so every engine starts from the same bed).
template <std::unique_ptr<Engine> (*Make)(const Scene&, std::vector<BodySpec>)>
std::unique_ptr<Engine> with_expanded_beds(const Scene& scene) {
  if (scene.dimension == 3 && !scene.assemblies.empty()) {
    Scene expanded = scene;  // (the engines keep a copy)
    expanded.bodies3d = dem::expanded_bodies3d(scene);
    expanded.assemblies.clear();
    return Make(expanded, std::vector<BodySpec>());
  }
  return Make(scene, dem::expanded_bodies(scene));
}
}  // namespace

// One row per engine: what it can do and how to make it. Effects are listed per engine: an engine
// claims only what it models.
const std::vector<Capabilities>& engine_catalog() {
  const std::vector<std::string> shapes2d = {"disc", "polygon", "segment", "line", "moving wall"};
  const std::vector<std::string> both = {"disc",        "polygon", "segment",    "line",
                                         "moving wall", "sphere",  "polyhedron", "plane"};
  std::vector<std::string> native_shapes = both;
  native_shapes.push_back("moving plane");  // the rigid engines' 3-D planes are static
  native_shapes.push_back("held body");     // 3-D bodies held in place (an impact's active zone)
  const std::vector<std::string> rigid_effects = {"gravity", "normal_contact", "friction", "rotation"};
  static const std::vector<Capabilities> all = {
      {"native",
       "the thesis's soft-contact DEM (eq. 2.3, predictor-corrector or Verlet), double precision; 3-D "
       "spheres and polyhedra with a Verlet list for spheres",
       {2, 3},
       native_shapes,
       known_effect_names(),
       true,
       true,
       0,
       "spring-dashpot normal force, incremental shear spring capped at mu f_n (kept in the tangent plane "
       "in 3-D)",
       "normal force of every contact, trapezoid over each accepted step (the integrators' own rule)",
       true,
       make_native_engine,
       true},
      {"box2d",
       "Box2D 2.4.1 (Debian), float precision, sequential impulses",
       {2},
       shapes2d,
       rigid_effects,
       false,
       true,
       8,
       "rigid contacts with restitution and Coulomb friction set per contact; stiffness is not modelled",
       "2-D: normal impulses from PostSolve, summed per pair and step",
       false,
       with_expanded_beds<make_box2d_engine>},
      {"ode",
       "ODE 0.16.2 (Debian), double precision; 2-D through plane-2D joints",
       {2, 3},
       both,
       rigid_effects,
       false,
       true,
       0,
       "rigid contacts (LCP) with restitution (bounce) and Coulomb friction set per contact; stiffness is "
       "not modelled",
       "2-D and 3-D: contact-joint feedback force along the normal times the step",
       false,
       with_expanded_beds<make_ode_engine>},
      {"bullet",
       "Bullet 3.24 (Debian, float64 libraries); 2-D through linear and angular factors",
       {2, 3},
       both,
       rigid_effects,
       false,
       true,
       0,
       "rigid contacts (sequential impulses) with restitution and Coulomb friction set per contact; "
       "stiffness is not modelled",
       "2-D and 3-D: applied impulses of the contact manifolds after each step",
       false,
       with_expanded_beds<make_bullet_engine>},
  };
  return all;
}

const Capabilities& engine_capabilities(const std::string& name) {
  for (const Capabilities& c : engine_catalog())
    if (c.name == name) return c;
  throw InputError(
      {"--engine", 0}, "engine",
      fmt::format("unknown engine \"{}\"; available: {}", name, fmt::join(engine_names(), ", ")));
}

std::unique_ptr<Engine> make_engine(const std::string& name, const Scene& scene) {
  const Capabilities& c = engine_capabilities(name);
  check_engine_supports(c, scene);
  return c.make(scene);
}

std::vector<std::string> engine_names() {
  std::vector<std::string> names;
  for (const Capabilities& c : engine_catalog()) names.push_back(c.name);
  return names;
}

std::vector<std::string> engines_for_dimension(int dimension) {
  std::vector<std::string> names;
  for (const Capabilities& c : engine_catalog())
    if (std::find(c.dimensions.begin(), c.dimensions.end(), dimension) != c.dimensions.end())
      names.push_back(c.name);
  return names;
}

namespace {
bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

[[noreturn]] void missing(const Capabilities& c, const std::string& what) {
  throw InputError({"--engine", 0}, c.name, fmt::format("engine \"{}\" cannot {}", c.name, what));
}
}  // namespace

void check_engine_supports(const Capabilities& c, const Scene& scene) {
  if (std::find(c.dimensions.begin(), c.dimensions.end(), scene.dimension) == c.dimensions.end())
    missing(c, fmt::format("run a {}-D scene", scene.dimension));
  for (const std::string& e : scene.effects.names())
    if (!has(c.effects, e)) missing(c, "simulate the effect \"" + e + "\"");
  if (scene.periodic_x && !c.periodic) missing(c, "do periodic boundaries (scene.periodic_x)");
  if (!scene.assemblies.empty() && !c.generated_assemblies) missing(c, "build generated assemblies");
  for (const BodySpec& b : scene.bodies) {
    const std::string shape = b.shape == BodySpec::Shape::Disc ? "disc" : "polygon";
    if (!has(c.shapes, shape)) missing(c, "handle " + shape + " bodies");
    if (c.max_polygon_vertices > 0 && static_cast<int>(b.vertices.size()) > c.max_polygon_vertices)
      missing(c, fmt::format("handle a polygon with {} vertices (at most {}; body id {})", b.vertices.size(),
                             c.max_polygon_vertices, b.id));
  }
  for (const Body3Spec& b : scene.bodies3d) {
    const std::string shape = b.shape == Body3Spec::Shape::Sphere ? "sphere" : "polyhedron";
    if (!has(c.shapes, shape)) missing(c, "handle " + shape + " bodies");
    if (b.held && !has(c.shapes, "held body"))
      missing(c, fmt::format("hold a body in place (body id {}: an impact's active zone)", b.id));
  }
  if (!scene.planes.empty() && !has(c.shapes, "plane")) missing(c, "handle plane walls");
  for (const PlaneSpec& p : scene.planes)
    if (p.motion.active() && !has(c.shapes, "moving plane")) missing(c, "move planes");
  for (const WallSpec& w : scene.walls) {
    if (!has(c.shapes, w.kind == WallSpec::Kind::Line ? "line" : "segment"))
      missing(c, "handle this wall type");
    if (w.motion.active() && !has(c.shapes, "moving wall")) missing(c, "move walls");
  }
}

double impulse_engine_restitution(const Material& m, double meff) {
  switch (m.normal_damping.kind) {
    case Damping::Kind::None:
      return 1.0;
    case Damping::Kind::Restitution:
      return m.normal_damping.value;
    case Damping::Kind::Rate:
      return dem::restitution_from_damping(m.k_n, m.normal_damping.value * meff, meff);
    case Damping::Kind::Coefficient:
      return dem::restitution_from_damping(m.k_n, m.normal_damping.value, meff);
  }
  return 1.0;
}

Vec2 wall_offset(const Motion& m, double t) {
  if (!m.active()) return {};
  const double om = 2 * M_PI * m.frequency;
  return {m.amplitude.x * std::sin(om * t + m.phase.x), m.amplitude.y * std::sin(om * t + m.phase.y)};
}

double unit_per_median_diameter(const std::vector<BodySpec>& bodies) {
  std::vector<double> sizes;
  for (const BodySpec& b : bodies) sizes.push_back(2 * b.radius);
  if (sizes.empty()) return 1.0;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  return 1.0 / sizes[sizes.size() / 2];
}

std::vector<std::vector<double>> polygon_outlines(const std::vector<BodySpec>& bodies) {
  std::vector<std::vector<double>> out;
  for (const BodySpec& b : bodies)
    if (b.shape == BodySpec::Shape::Polygon) {
      std::vector<double> flat;
      for (Vec2 v : b.vertices) flat.insert(flat.end(), {v.x, v.y});
      out.push_back(flat);
    }
  return out;
}

double unit_per_median_diameter(const std::vector<Body3Spec>& bodies) {
  std::vector<double> sizes;
  for (const Body3Spec& b : bodies) sizes.push_back(2 * b.radius);
  if (sizes.empty()) return 1.0;
  std::nth_element(sizes.begin(), sizes.begin() + sizes.size() / 2, sizes.end());
  return 1.0 / sizes[sizes.size() / 2];
}

std::vector<std::vector<double>> polyhedron_vertices(const std::vector<Body3Spec>& bodies) {
  std::vector<std::vector<double>> out;
  for (const Body3Spec& b : bodies)
    if (b.shape == Body3Spec::Shape::Polyhedron) {
      std::vector<double> flat;
      for (const Vec3& v : b.hull.vertices) flat.insert(flat.end(), {v.x(), v.y(), v.z()});
      out.push_back(flat);
    }
  return out;
}

void append_body3d(Frame& f, const Body3Spec& b, std::int32_t shape_index, const Vec3& x, const Vec3& v,
                   const Quat& q, const Vec3& w) {
  const double qq[4] = {q.w(), q.x(), q.y(), q.z()};
  f.add_body3d(b.id, x.data(), v.data(), qq, w.data(), b.radius, shape_index);
}

std::vector<std::int32_t> polyhedron_indices(const std::vector<Body3Spec>& bodies) {
  std::vector<std::int32_t> idx;
  std::int32_t next = 0;
  for (const Body3Spec& b : bodies) idx.push_back(b.shape == Body3Spec::Shape::Polyhedron ? next++ : -1);
  return idx;
}

EnergyReport rigid_body_energies(const Frame& f, const std::vector<Body3Spec>& bodies, const Scene& scene) {
  EnergyReport e;
  const Vec3 g = scene.effects.has(Effect::gravity) ? scene.gravity3d : Vec3::Zero();
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const Body3Spec& b = bodies[k];
    const Vec3 x(&f.position[3 * k]), v(&f.velocity[3 * k]), w(&f.angular_velocity[3 * k]);
    const Quat q(f.orientation[4 * k], f.orientation[4 * k + 1], f.orientation[4 * k + 2],
                 f.orientation[4 * k + 3]);
    const Mat3 R = q.toRotationMatrix();
    e.kinetic_translational += 0.5 * b.mass * v.squaredNorm();
    e.kinetic_rotational += 0.5 * w.dot(R * b.inertia * R.transpose() * w);
    e.potential_gravity -= b.mass * g.dot(x);
  }
  return e;
}

EnergyReport rigid_body_energies(const Frame& f, const std::vector<BodySpec>& bodies, const Scene& scene) {
  EnergyReport e;
  const Vec2 g = scene.effects.has(Effect::gravity) ? scene.gravity : Vec2{};
  for (std::size_t k = 0; k < bodies.size(); ++k) {
    const BodySpec& b = bodies[k];
    const double vx = f.velocity[3 * k], vy = f.velocity[3 * k + 1];
    e.kinetic_translational += 0.5 * b.mass * (vx * vx + vy * vy);
    e.kinetic_rotational += 0.5 * b.inertia * f.spin[k] * f.spin[k];
    e.potential_gravity -= b.mass * (g.x * f.position[3 * k] + g.y * f.position[3 * k + 1]);
  }
  return e;  // rigid contacts store no elastic energy
}

}  // namespace grainlab
