#include "scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <unordered_map>

#include "polygon.hpp"
#include "toml_reader.hpp"

namespace grainlab {

namespace {

// The pairs (i < j) of bounding spheres that overlap, ascending by (i, j), found through a grid of cells
// one largest diameter wide: a scene of 100,000 bodies is checked in well under a second.
std::vector<std::pair<std::size_t, std::size_t>> overlapping_bounds(const std::vector<Vec3>& centre,
                                                                    const std::vector<double>& radius) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  const double r_max = radius.empty() ? 0 : *std::max_element(radius.begin(), radius.end());
  if (!(r_max > 0)) return out;
  const double cell = 2 * r_max;
  auto key = [](long x, long y, long z) {
    return (static_cast<std::uint64_t>(x) & 0x1FFFFF) | (static_cast<std::uint64_t>(y) & 0x1FFFFF) << 21 |
           (static_cast<std::uint64_t>(z) & 0x1FFFFF) << 42;
  };
  auto coord = [&](double v) { return static_cast<long>(std::floor(v / cell)); };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i < centre.size(); ++i)
    cells[key(coord(centre[i].x()), coord(centre[i].y()), coord(centre[i].z()))].push_back(i);
  for (std::size_t i = 0; i < centre.size(); ++i) {
    const long cx = coord(centre[i].x()), cy = coord(centre[i].y()), cz = coord(centre[i].z());
    const std::size_t first = out.size();
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (std::size_t j : it->second)
            if (j > i && (centre[i] - centre[j]).norm() < radius[i] + radius[j]) out.push_back({i, j});
        }
    std::sort(out.begin() + static_cast<long>(first), out.end());
  }
  return out;
}

Effects read_effects(const TomlReader& r) {
  Effects e;
  const std::string known = fmt::format("{}", fmt::join(known_effect_names(), ", "));
  if (!r.has("effects")) r.fail("effects", "required: list the effects this scene needs, from " + known);
  std::set<std::string> seen;
  for (const std::string& name : r.string_list("effects")) {
    if (!seen.insert(name).second) r.fail("effects", "\"" + name + "\" is listed twice");
    const std::optional<Effect> id = effect_named(name);
    if (!id) r.fail("effects", fmt::format("unknown effect \"{}\"; known: {}", name, known));
    e.set(*id);
  }
  for (const EffectInfo& info : effect_registry())
    for (Effect need : info.needs)
      if (e.has(info.id) && !e.has(need))
        r.fail("effects", fmt::format("\"{}\" needs \"{}\"", info.name, effect_info(need).name));
  return e;
}

Damping read_damping(const TomlReader& r, const char* rate_key, const char* coef_key, const char* rest_key) {
  std::vector<std::string> given;
  for (const char* k : {rate_key, coef_key, rest_key})
    if (k && r.has(k)) given.emplace_back(k);
  if (given.size() > 1)
    r.fail(given[1],
           fmt::format("give only one of {}: they specify the same damping", fmt::join(given, ", ")));
  Damping d;
  if (r.has(rate_key))
    d = {Damping::Kind::Rate, r.number(rate_key, Range::non_negative())};
  else if (r.has(coef_key))
    d = {Damping::Kind::Coefficient, r.number(coef_key, Range::non_negative())};
  else if (rest_key && r.has(rest_key))
    d = {Damping::Kind::Restitution, r.number(rest_key, Range::closed(0, 1))};  // 0: critically damped
  return d;
}

void read_material_body(const TomlReader& r, Material& m) {
  m.k_n = r.number("k_n", Range::positive());
  m.normal_damping = read_damping(r, "gamma_n", "damping_n", "restitution");
  m.k_s = r.number_or("k_s", 0.0, Range::non_negative());
  m.shear_damping = read_damping(r, "gamma_s", "damping_s", nullptr);
  m.mu = r.number_or("mu", 0.0, Range::non_negative());
}

Motion3 read_motion3(const TomlReader& parent) {
  Motion3 m;
  const toml::table* t = parent.subtable("motion");
  if (!t) return m;
  TomlReader r(*t, parent.dotted("motion"), "");
  const std::vector<double> a = r.numbers("amplitude", 3);
  m.amplitude = Vec3(a[0], a[1], a[2]);
  m.frequency = r.number("frequency", Range::positive());
  if (r.has("phase")) {
    const std::vector<double> p = r.numbers("phase", 3);
    m.phase = Vec3(p[0], p[1], p[2]);
  }
  r.finish();
  return m;
}

Motion read_motion(const TomlReader& parent) {
  Motion m;
  const toml::table* t = parent.subtable("motion");
  if (!t) return m;
  TomlReader r(*t, parent.dotted("motion"), "");
  m.amplitude = r.vec2("amplitude");
  m.frequency = r.number("frequency", Range::positive());
  m.phase = r.vec2_or("phase", {0, 0});
  r.finish();
  return m;
}

SizeDistribution read_size(const TomlReader& r) {
  SizeDistribution s;
  if (r.has("radius")) {
    s = {SizeDistribution::Kind::Fixed, r.number("radius", Range::positive()), 0};
    return s;
  }
  const toml::table* t = r.subtable("radius_distribution");
  if (!t) r.fail("radius", "required: give radius or a [radius_distribution] table");
  TomlReader d(*t, r.dotted("radius_distribution"), "");
  const std::string kind = d.string("kind");
  if (kind == "uniform") {
    s = {SizeDistribution::Kind::Uniform, d.number("min", Range::positive()),
         d.number("max", Range::positive())};
    if (s.b < s.a) d.fail("max", "must be >= min");
  } else if (kind == "normal") {
    s = {SizeDistribution::Kind::Normal, d.number("mean", Range::positive()),
         d.number("sd", Range::non_negative())};
    if (s.a - 3 * s.b <= 0) d.fail("sd", "mean - 3 sd must stay positive (radii are truncated at +-3 sd)");
  } else {
    d.fail("kind", "must be \"uniform\" or \"normal\", found \"" + kind + "\"");
  }
  d.finish();
  return s;
}

// Limits that keep a hostile or mistyped scene from running forever or exhausting memory.
constexpr double kMaxSteps = 1e12, kMaxGenerated = 1e7;

class SceneReader {
 public:
  SceneReader(const toml::table& root, Scene& scene) : root_(root), s_(scene) {}

  void read() {
    TomlReader top(root_, "", s_.path);
    read_scene_section(top);
    read_contact_section(top);
    read_accuracy_section(top);
    read_materials(top);
    read_bodies(top);
    read_walls(top);
    read_assemblies(top);
    read_output(top);
    read_fluid(top);
    read_wind(top);
    top.finish();
    check_pairs_exist(top);
    check_ids();
    check_initial_overlaps();
    convert_to_cgs();
  }

  // Everything in cgs from here on. In 2-D a mass is per unit thickness in the thesis's sense (a disc
  // of density rho, mass per area, has mass rho pi r^2), so densities scale as mass / length^2.
  void convert_to_cgs() {
    const Scene::UnitScale u = s_.to_cgs;
    if (u.length == 1 && u.mass == 1 && u.time == 1) return;
    const double L = u.length, M = u.mass, V = u.velocity(), A = L / (u.time * u.time);
    const double K = M / (u.time * u.time),
                 C = M / u.time;  // stiffness (force/length), damping (force/velocity)
    auto len = [L](Vec2& v) { v = v * L; };
    s_.gravity = s_.gravity * A;
    for (auto* p : {&s_.periodic_x, &s_.periodic_y})
      if (*p) *p = std::make_pair((*p)->first * L, (*p)->second * L);
    s_.accuracy.velocity_floor *= V;
    if (s_.accuracy.skin) *s_.accuracy.skin *= L;
    auto material = [&](Material& m) {
      m.k_n *= K;
      m.k_s *= K;
      for (Damping* d : {&m.normal_damping, &m.shear_damping})
        if (d->kind == Damping::Kind::Coefficient) d->value *= C;  // rates and restitutions are unit-free
    };
    for (Material& m : s_.materials) material(m);
    for (auto& [k, m] : s_.pair_materials) material(m);
    for (BodySpec& b : s_.bodies) {
      b.radius *= L;
      for (Vec2& v : b.vertices) len(v);
      b.mass *= M;
      b.inertia *= M * L * L;
      len(b.position);
      b.velocity = b.velocity * V;
      b.spin /= u.time;
    }
    for (Body3Spec& b : s_.bodies3d) {
      b.radius *= L;
      for (Vec3& v : b.hull.vertices) v *= L;
      for (double& d : b.hull.offsets) d *= L;
      b.mass *= M;
      b.inertia *= M * L * L;
      b.position *= L;
      b.velocity *= V;
      b.spin /= u.time;
    }
    s_.gravity3d *= A;
    for (PlaneSpec& p : s_.planes) p.point *= L, p.motion.amplitude *= L, p.motion.frequency /= u.time;
    for (WallSpec& w : s_.walls) {
      len(w.a);
      if (w.kind == WallSpec::Kind::Segment) len(w.b);
      len(w.motion.amplitude);
      w.motion.frequency /= u.time;
    }
    for (AssemblySpec& a : s_.assemblies) {
      a.spacing *= L;
      len(a.origin);
      a.width *= L;
      a.settle_time *= u.time;
      a.radius.a *= L;  // fixed radius, minimum or mean
      a.radius.b *= L;  // maximum or standard deviation
      a.density *= a.spheres ? M / (L * L * L) : M / (L * L);
      a.velocity = a.velocity * V;
      a.origin3 *= L, a.velocity3 *= V, a.depth *= L;
    }
    // The fluid: densities are 3-D (mass / length^3) whatever the dimension.
    s_.fluid.density *= M / (L * L * L);
    s_.fluid.grain_density *= M / (L * L * L);
    s_.fluid.viscosity *= L * L / u.time;
    WindSpec& w = s_.wind;
    w.u_star *= V;
    for (double* len_key : {&w.roughness, &w.bin_height, &w.top, &w.thickness}) *len_key *= L;
    if (w.bed_level) *w.bed_level *= L;
    w.update_interval *= u.time;
    s_.duration *= u.time;
    s_.accuracy.dt *= u.time;
    s_.accuracy.dt_min *= u.time;
    s_.accuracy.dt_max *= u.time;
  }

 private:
  TomlReader section(const TomlReader& top, const std::string& key, bool required) {
    const toml::table* t = top.subtable(key);
    if (!t) {
      if (required) throw InputError({s_.path, 0}, key, "required section [" + key + "] is missing");
      return TomlReader(empty_, key, s_.path);
    }
    return TomlReader(*t, key, s_.path);
  }

  void read_scene_section(const TomlReader& top) {
    TomlReader r = section(top, "scene", true);
    s_.name = r.string_or("name", "unnamed");
    s_.dimension = static_cast<int>(r.integer_or("dimension", 2, 2, 3));
    s_.units = r.string_or("units", "cgs");
    if (s_.units == "si")
      s_.to_cgs = {100.0, 1000.0, 1.0};
    else if (s_.units != "cgs")
      r.fail("units", "must be \"cgs\" (cm, g, s) or \"si\" (m, kg, s), found \"" + s_.units + "\"");
    s_.duration = r.number("duration", Range::positive());
    s_.seed = static_cast<std::uint64_t>(r.integer_or("seed", 0, 0, INT64_MAX));
    if (s_.dimension == 3) {
      if (r.has("gravity")) s_.gravity3d = vec3(r.numbers("gravity", 3));
    } else {
      s_.gravity = r.vec2_or("gravity", {0, -981.0});
    }
    if (r.has("periodic_y") && s_.dimension != 3)
      r.fail("periodic_y", "is for 3-D scenes (a 2-D scene is periodic in x only)");
    for (const char* key : {"periodic_x", "periodic_y"}) {
      if (!r.has(key)) continue;
      const Vec2 p = r.vec2(key);
      if (!(p.y > p.x)) r.fail(key, "must be [min, max] with max > min");
      (key[9] == 'x' ? s_.periodic_x : s_.periodic_y) = std::make_pair(p.x, p.y);
    }
    s_.effects = read_effects(r);
    r.finish();
  }

  void read_contact_section(const TomlReader& top) {
    TomlReader r = section(top, "contact", false);
    s_.clip_attractive_normal_force = r.boolean_or("clip_attractive", false);
    s_.overlap_tolerance = r.number_or("overlap_tolerance", 0.01, Range::closed(0, 1));
    r.finish();
  }

  void read_accuracy_section(const TomlReader& top) {
    TomlReader r = section(top, "accuracy", false);
    Accuracy& a = s_.accuracy;
    const std::string integ = r.string_or("integrator", "predictor-corrector");
    if (integ == "predictor-corrector")
      a.integrator = Integrator::PredictorCorrector;
    else if (integ == "verlet")
      a.integrator = Integrator::VelocityVerlet;
    else
      r.fail("integrator", "must be \"predictor-corrector\" or \"verlet\", found \"" + integ + "\"");
    a.tolerance = r.number_or("tolerance", a.tolerance, {0, 1, true});
    const std::string measure = r.string_or("error_measure", "velocity");
    if (measure == "velocity")
      a.error_measure = ErrorMeasure::Velocity;
    else if (measure == "change")
      a.error_measure = ErrorMeasure::Change;
    else
      r.fail("error_measure", "must be \"velocity\" or \"change\", found \"" + measure + "\"");
    a.velocity_floor = r.number_or("velocity_floor", a.velocity_floor, Range::positive());
    a.dt = r.number_or("dt", a.dt, Range::positive());
    a.dt_min = r.number_or("dt_min", a.dt_min, Range::positive());
    a.dt_max = r.number_or("dt_max", std::max(a.dt_max, a.dt), Range::positive());
    a.skin = r.optional_number("skin", Range::positive());
    a.velocity_iterations = static_cast<int>(r.integer_or("velocity_iterations", 8, 1, 100000));
    a.position_iterations = static_cast<int>(r.integer_or("position_iterations", 3, 0, 100000));
    a.substeps = static_cast<int>(r.integer_or("substeps", 1, 1, 100000));
    a.stepper = r.string_or("stepper", "auto");
    if (a.stepper != "step" && a.stepper != "quick" && a.stepper != "auto")
      r.fail("stepper", "must be \"step\", \"quick\" or \"auto\", found \"" + a.stepper + "\"");
    a.erp = r.optional_number("erp", Range::closed(0, 1));
    a.cfm = r.optional_number("cfm", Range::non_negative());
    a.split_impulse = r.boolean_or("split_impulse", true);
    if (a.dt_min > a.dt) r.fail("dt_min", "must not exceed dt");
    if (a.dt_max < a.dt) r.fail("dt_max", "must not be below dt");
    // A run that could never finish is a mistake, not a long run: at least duration / (the largest step)
    // steps, and beyond 1e12 even one grain takes hours.
    const double largest = a.integrator == Integrator::VelocityVerlet ? a.dt : a.dt_max;
    if (s_.duration / largest > kMaxSteps)
      r.fail(a.integrator == Integrator::VelocityVerlet ? "dt" : "dt_max",
             fmt::format(
                 "scene.duration {} s at steps of at most {} s needs at least {:.3g} steps; more than {:.0e} "
                 "would never finish (shorten the duration or lengthen the step)",
                 s_.duration, largest, s_.duration / largest, kMaxSteps));
    r.finish();
  }

  void read_materials(const TomlReader& top) {
    const toml::table* mats = top.subtable("materials");
    if (!mats) return;
    TomlReader all(*mats, "materials", s_.path);
    for (const auto& [k, v] : *mats) {
      const std::string name(k.str());
      const toml::table* t = all.subtable(name);
      TomlReader r(*t, all.dotted(name), s_.path);
      Material m;
      m.name = name;
      read_material_body(r, m);
      check_material(r, m);
      r.finish();
      material_index_[name] = static_cast<int>(s_.materials.size());
      s_.materials.push_back(m);
    }
    if (const toml::array* pairs = top.array_of_tables("material_pairs")) {
      for (size_t i = 0; i < pairs->size(); ++i) {
        TomlReader r(*(*pairs)[i].as_table(), fmt::format("material_pairs[{}]", i), s_.path);
        const std::vector<std::string> between = r.string_list("between");
        if (between.size() != 2) r.fail("between", "must name exactly two materials");
        const int a = material_ref(r, "between", between[0]), b = material_ref(r, "between", between[1]);
        Material m;
        m.name = between[0] + "|" + between[1];
        read_material_body(r, m);
        check_material(r, m);
        r.finish();
        s_.pair_materials[{std::min(a, b), std::max(a, b)}] = m;
      }
    }
  }

  void check_material(const TomlReader& r, const Material& m) {
    if (s_.effects.has(Effect::friction) && m.k_s <= 0)
      r.fail("k_s", "the scene lists \"friction\", so the shear spring k_s must be given and > 0");
  }

  int material_ref(const TomlReader& r, const std::string& key, const std::string& name) {
    auto it = material_index_.find(name);
    if (it == material_index_.end())
      r.fail(key, "no material named \"" + name + "\" (define it as [materials." + name + "])");
    return it->second;
  }

  int material_of(const TomlReader& r) {
    if (r.has("material")) {
      const int m = material_ref(r, "material", r.string("material"));
      used_materials_.insert(m);
      return m;
    }
    if (s_.materials.size() == 1) return used_materials_.insert(0), 0;
    if (!s_.effects.has(Effect::normal_contact)) return 0;
    r.fail("material", s_.materials.empty() ? "the scene has contacts but defines no [materials.NAME]"
                                            : "required when the scene defines more than one material");
  }

  void read_bodies(const TomlReader& top) {
    const toml::array* bodies = top.array_of_tables("bodies");
    if (!bodies) return;
    if (s_.dimension == 3) return read_bodies3d(*bodies);
    for (size_t i = 0; i < bodies->size(); ++i) {
      TomlReader r(*(*bodies)[i].as_table(), fmt::format("bodies[{}]", i), s_.path);
      BodySpec b;
      b.where = r.where_table();
      b.id = r.integer_or("id", static_cast<std::int64_t>(i), 0, INT64_MAX);
      const std::string shape = r.string_or("shape", "disc");
      double area = 0, polar = 0;
      if (shape == "disc") {
        b.shape = BodySpec::Shape::Disc;
        b.radius = r.number("radius", Range::positive());
        area = M_PI * b.radius * b.radius;
        polar = area * b.radius * b.radius / 2;
      } else if (shape == "polygon") {
        b.shape = BodySpec::Shape::Polygon;
        b.vertices = r.vec2_list("vertices");
        if (b.vertices.size() < 3) r.fail("vertices", "a polygon needs at least 3 vertices");
        if (!is_convex_ccw(b.vertices))
          r.fail("vertices",
                 "must be a convex polygon listed counter-clockwise (no repeated or collinear points)");
        raw_vertices_ = b.vertices;
        const PolygonMass pm = polygon_mass(b.vertices);
        for (Vec2& v : b.vertices) v -= pm.centroid;  // body frame at the centroid
        area = pm.area;
        polar = pm.polar_moment_per_density;
        b.radius = bounding_radius(b.vertices);
      } else {
        r.fail("shape", "must be \"disc\" or \"polygon\", found \"" + shape + "\"");
      }
      read_mass(r, b, area, polar);
      if (b.shape == BodySpec::Shape::Polygon && r.has("center_of_mass")) load_polygon(r, b);
      if (r.has("inertia")) b.inertia = r.number("inertia", Range::positive());
      b.position = r.vec2("position");
      b.velocity = r.vec2_or("velocity", {0, 0});
      b.angle = r.number_or("angle", 0.0);
      b.spin = r.number_or("spin", 0.0);
      b.material = material_of(r);
      r.finish();
      s_.bodies.push_back(std::move(b));
    }
  }

  // A loaded body: its centre of mass, given in the frame the vertices are written in, becomes the
  // body's origin (the position is then that of the centre of mass). Unless `inertia` is given, the
  // moment is the uniform body's about its centroid moved to the centre of mass (parallel axis).
  void load_polygon(const TomlReader& r, BodySpec& b) {
    const Vec2 com = r.vec2("center_of_mass");
    const PolygonMass pm = polygon_mass(raw_vertices_);
    if (!point_in_convex(com, raw_vertices_))
      r.fail("center_of_mass", "must lie inside the polygon (in the frame the vertices are given in)");
    const Vec2 shift = com - pm.centroid;
    for (Vec2& v : b.vertices) v -= shift;
    b.inertia += b.mass * dot(shift, shift);
    b.radius = bounding_radius(b.vertices);
  }

  void read_mass(const TomlReader& r, BodySpec& b, double area, double polar) {
    if (r.has("mass") && r.has("density")) r.fail("density", "give mass or density, not both");
    if (r.has("mass"))
      b.mass = r.number("mass", Range::positive());
    else if (r.has("density"))
      b.mass = r.number("density", Range::positive()) * area;
    else
      r.fail("density", "required: give the body's density (mass per area) or its mass");
    b.inertia = b.mass * polar / area;
  }

  static Vec3 vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

  void read_bodies3d(const toml::array& bodies) {
    for (size_t i = 0; i < bodies.size(); ++i) {
      TomlReader r(*bodies[i].as_table(), fmt::format("bodies[{}]", i), s_.path);
      Body3Spec b;
      b.where = r.where_table();
      b.id = r.integer_or("id", static_cast<std::int64_t>(i), 0, INT64_MAX);
      const std::string kind = r.string_or("shape", "sphere");
      SolidMass solid;
      if (kind == "sphere") {
        b.shape = Body3Spec::Shape::Sphere;
        b.radius = r.number("radius", Range::positive());
        solid.volume = 4 * M_PI / 3 * std::pow(b.radius, 3);
        solid.inertia_per_density = Mat3::Identity() * 0.4 * solid.volume * b.radius * b.radius;
        if (r.has("center_of_mass")) r.fail("center_of_mass", "a sphere's centre of mass is its centre");
      } else if (kind == "box" || kind == "polyhedron") {
        b.shape = Body3Spec::Shape::Polyhedron;
        if (kind == "box") {
          const Vec3 size = vec3(r.numbers("size", 3));
          if (size.minCoeff() <= 0) r.fail("size", "edge lengths must be > 0");
          b.hull = make_box(size / 2);
        } else {
          std::vector<Vec3> v;
          for (const auto& row : r.number_rows("vertices", 3)) v.push_back(vec3(row));
          const std::string err = make_polyhedron(v, r.index_lists("faces"), b.hull);
          if (!err.empty()) r.fail("faces", err);
        }
        solid = polyhedron_mass(b.hull);
        b.hull.translate(-solid.centroid);  // body frame at the centroid until a load moves it
      } else {
        r.fail("shape",
               "must be \"sphere\", \"box\" or \"polyhedron\" in a 3-D scene, found \"" + kind + "\"");
      }
      if (r.has("mass") && r.has("density")) r.fail("density", "give mass or density, not both");
      if (r.has("mass"))
        b.mass = r.number("mass", Range::positive());
      else if (r.has("density"))
        b.mass = r.number("density", Range::positive()) * solid.volume;
      else
        r.fail("density", "required: give the body's density (mass per volume) or its mass");
      b.inertia = solid.inertia_per_density * (b.mass / solid.volume);
      if (r.has("center_of_mass")) load_polyhedron(r, b, solid);
      if (r.has("inertia")) b.inertia = read_inertia(r);
      if (b.shape == Body3Spec::Shape::Polyhedron) b.radius = b.hull.bounding_radius();
      b.position = vec3(r.numbers("position", 3));
      if (r.has("velocity")) b.velocity = vec3(r.numbers("velocity", 3));
      if (r.has("orientation")) {
        const std::vector<double> q = r.numbers("orientation", 4);
        b.orientation = Quat(q[0], q[1], q[2], q[3]);
        if (b.orientation.norm() < 1e-12) r.fail("orientation", "a quaternion [w, x, y, z] must not be zero");
        b.orientation.normalize();
      }
      if (r.has("spin")) b.spin = vec3(r.numbers("spin", 3));
      b.material = material_of(r);
      r.finish();
      s_.bodies3d.push_back(std::move(b));
    }
  }

  // A loaded polyhedron: the centre of mass, in the frame the geometry is written in (a box's centre
  // is its origin), becomes the body origin; the inertia moves to it by the parallel-axis theorem.
  void load_polyhedron(const TomlReader& r, Body3Spec& b, const SolidMass& solid) {
    const Vec3 com = vec3(r.numbers("center_of_mass", 3)) - solid.centroid;  // relative to the centroid
    if (!b.hull.contains(com)) r.fail("center_of_mass", "must lie inside the body");
    b.hull.translate(-com);
    b.inertia += b.mass * (com.squaredNorm() * Mat3::Identity() - com * com.transpose());
  }

  // Three principal moments along the body axes, or the full symmetric 3 x 3 tensor.
  Mat3 read_inertia(const TomlReader& r) {
    Mat3 I = Mat3::Zero();
    const toml::node* n = r.node("inertia");
    const bool rows = n && n->as_array() && !n->as_array()->empty() && (*n->as_array())[0].is_array();
    if (rows) {
      const auto m = r.number_rows("inertia", 3);
      if (m.size() != 3) r.fail("inertia", "a tensor needs 3 rows of 3 numbers");
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) I(i, j) = m[i][j];
      if ((I - I.transpose()).norm() > 1e-12 * I.norm()) r.fail("inertia", "the tensor must be symmetric");
    } else {
      const Vec3 d = vec3(r.numbers("inertia", 3));
      I = d.asDiagonal();
    }
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(I);
    const Vec3 p = eig.eigenvalues();
    if (p.minCoeff() <= 0) r.fail("inertia", "the principal moments must be > 0");
    if (p(0) + p(1) < p(2) * (1 - 1e-12))
      r.fail("inertia", "violates the triangle inequality (no rigid body has these principal moments)");
    return I;
  }

  void read_planes(const toml::array& walls) {
    for (size_t i = 0; i < walls.size(); ++i) {
      TomlReader r(*walls[i].as_table(), fmt::format("walls[{}]", i), s_.path);
      PlaneSpec p;
      p.where = r.where_table();
      const std::string type = r.string_or("type", "plane");
      if (type != "plane") r.fail("type", "3-D scenes take walls of type \"plane\", found \"" + type + "\"");
      p.point = vec3(r.numbers("point", 3));
      p.normal = vec3(r.numbers("normal", 3));
      if (p.normal.norm() == 0) r.fail("normal", "must be a non-zero vector");
      p.normal.normalize();
      p.motion = read_motion3(r);
      p.material = material_of(r);
      r.finish();
      s_.planes.push_back(p);
    }
  }

  void read_walls(const TomlReader& top) {
    const toml::array* walls = top.array_of_tables("walls");
    if (!walls) return;
    if (s_.dimension == 3) return read_planes(*walls);
    for (size_t i = 0; i < walls->size(); ++i) {
      TomlReader r(*(*walls)[i].as_table(), fmt::format("walls[{}]", i), s_.path);
      WallSpec w;
      w.where = r.where_table();
      const std::string type = r.string_or("type", "segment");
      if (type == "segment") {
        w.kind = WallSpec::Kind::Segment;
        w.a = r.vec2("from");
        w.b = r.vec2("to");
        if (norm(w.b - w.a) == 0) r.fail("to", "a segment needs two distinct end points");
      } else if (type == "line") {
        w.kind = WallSpec::Kind::Line;
        w.a = r.vec2("point");
        const Vec2 n = r.vec2("normal");
        if (norm(n) == 0) r.fail("normal", "must be a non-zero vector");
        w.b = n * (1 / norm(n));
      } else {
        r.fail("type", "must be \"segment\" or \"line\", found \"" + type + "\"");
      }
      w.material = material_of(r);
      w.motion = read_motion(r);
      r.finish();
      s_.walls.push_back(w);
    }
  }

  // Generated beds: a lattice or a pour, of discs (2-D) or spheres (3-D: nz layers, a box depth along
  // y, density per volume).
  void read_assemblies(const TomlReader& top) {
    const toml::array* list = top.array_of_tables("assemblies");
    if (!list) return;
    const bool three_d = s_.dimension == 3;
    for (size_t i = 0; i < list->size(); ++i) {
      TomlReader r(*(*list)[i].as_table(), fmt::format("assemblies[{}]", i), s_.path);
      AssemblySpec a;
      a.where = r.where_table();
      const std::string type = r.string("type");
      a.radius = read_size(r);
      read_assembly_density(r, a, three_d);
      if (three_d) {
        a.origin3 = vec3(r.numbers("origin", 3));
        if (r.has("velocity")) a.velocity3 = vec3(r.numbers("velocity", 3));
        read_grain_shape(r, a, type);
      } else {
        a.velocity = r.vec2_or("velocity", {0, 0});
        a.origin = r.vec2("origin");
      }
      a.material = material_of(r);
      const double widest = 2 * max_radius(a.radius);
      if (type == "lattice") {
        a.kind = AssemblySpec::Kind::Lattice;
        a.nx = static_cast<int>(r.integer("nx", 1, 10'000'000));
        a.ny = static_cast<int>(r.integer("ny", 1, 10'000'000));
        a.nz = three_d ? static_cast<int>(r.integer("nz", 1, 10'000'000)) : 1;
        if (const double n = double(a.nx) * a.ny * a.nz; n > kMaxGenerated)
          r.fail(three_d ? "nz" : "ny", fmt::format("{} = {:.3g} {}; at most {:.0e} can be generated",
                                                    three_d ? "nx x ny x nz" : "nx x ny", n,
                                                    three_d ? "spheres" : "discs", kMaxGenerated));
        a.spacing = r.number("spacing", Range::positive());
        if (a.spacing < widest)
          r.fail("spacing",
                 fmt::format("{} is less than the largest diameter {}: the lattice would start overlapped",
                             a.spacing, widest));
      } else if (type == "poured") {
        a.kind = AssemblySpec::Kind::Poured;
        a.count = static_cast<int>(r.integer("count", 1, 10'000'000));
        a.width = r.number("width", Range::positive());
        if (three_d) a.depth = r.number("depth", Range::positive());
        a.settle_time = r.number_or("settle_time", 1.0, Range::positive());
        if (a.width < widest) r.fail("width", "narrower than one grain");
        if (three_d && a.depth < widest) r.fail("depth", "narrower than one grain");
      } else {
        r.fail("type", "must be \"lattice\" or \"poured\", found \"" + type + "\"");
      }
      r.finish();
      s_.assemblies.push_back(a);
    }
  }

  // 3-D: spheres (default) or irregular polyhedra, poured only.
  void read_grain_shape(const TomlReader& r, AssemblySpec& a, const std::string& type) {
    const std::string shape = r.string_or("shape", "sphere");
    if (shape != "sphere" && shape != "polyhedron")
      r.fail("shape", "must be \"sphere\" or \"polyhedron\", found \"" + shape + "\"");
    a.polyhedra = shape == "polyhedron";
    if (a.polyhedra && type != "poured")
      r.fail("shape", "polyhedral grains are poured, not laid on a lattice");
    if (!a.polyhedra && (r.has("irregularity") || r.has("elongation")))
      r.fail(r.has("irregularity") ? "irregularity" : "elongation", "only for shape = \"polyhedron\"");
    a.irregularity = r.number_or("irregularity", 0.2, Range::closed(0, 0.4));
    a.elongation = r.number_or("elongation", 0.2, Range::closed(0, 0.6));
  }

  // 2-D: density per area (discs) or sphere_density (each disc has its sphere's mass); 3-D: spheres,
  // density per volume.
  void read_assembly_density(const TomlReader& r, AssemblySpec& a, bool three_d) {
    if (three_d) {
      if (r.has("sphere_density"))
        r.fail("sphere_density", "3-D assemblies are spheres already: give density (mass per volume)");
      a.density = r.number("density", Range::positive());
      a.spheres = true;
      return;
    }
    if (r.has("density") == r.has("sphere_density"))
      r.fail("density",
             "give exactly one of density (mass per area: discs) and sphere_density (mass per "
             "volume: each disc has the mass of the sphere of its radius)");
    a.spheres = r.has("sphere_density");
    a.density = r.number(a.spheres ? "sphere_density" : "density", Range::positive());
  }

  static double max_radius(const SizeDistribution& d) {
    switch (d.kind) {
      case SizeDistribution::Kind::Fixed:
        return d.a;
      case SizeDistribution::Kind::Uniform:
        return d.b;
      case SizeDistribution::Kind::Normal:
        return d.a + 3 * d.b;
    }
    return d.a;
  }

  void read_output(const TomlReader& top) {
    TomlReader r = section(top, "output", false);
    s_.output.file = r.string_or("file", "");
    s_.output.frames = static_cast<int>(r.integer_or("frames", 50, 0, 1'000'000));
    s_.output.contacts = r.boolean_or("contacts", false);
    r.finish();
  }

  // A table read only by effects the scene does not list is a mistake (the wind would silently not blow).
  bool table_wanted(const TomlReader& top, const std::string& table) {
    std::vector<std::string> readers;
    bool wanted = false;
    for (const EffectInfo& e : effect_registry())
      for (const std::string& key : e.scene_keys)
        if (key == table || key.rfind(table + ".", 0) == 0) {
          readers.push_back("\"" + e.name + "\"");
          wanted = wanted || s_.effects.has(e.id);
          break;
        }
    if (!wanted && top.subtable(table))
      throw InputError(top.where_table(), table,
                       fmt::format("[{}] is read by the effect {}, which [scene] effects does not list",
                                   table, fmt::join(readers, " or ")));
    return wanted;
  }

  void read_fluid(const TomlReader& top) {
    if (!table_wanted(top, "fluid")) return;
    TomlReader r = section(top, "fluid", false);
    FluidSpec& f = s_.fluid;
    f.density = r.number_or("density", f.density, Range::non_negative());
    f.viscosity = r.number_or("viscosity", f.viscosity, Range::positive());
    f.grain_density = r.number_or("grain_density", f.grain_density, Range::positive());
    if (f.density >= f.grain_density)
      r.fail("density", "must be below grain_density (the grains would float)");
    r.finish();
  }

  void read_wind(const TomlReader& top) {
    if (!table_wanted(top, "wind")) return;
    TomlReader r = section(top, "wind", true);
    WindSpec& w = s_.wind;
    const std::string model = r.string_or("model", "mixing_length");
    if (model == "fixed")
      w.model = WindSpec::Model::Fixed;
    else if (model == "mixing_length")
      w.model = WindSpec::Model::MixingLength;
    else if (model == "van_driest")
      w.model = WindSpec::Model::VanDriest;
    else
      r.fail("model", "must be \"mixing_length\", \"van_driest\" or \"fixed\", found \"" + model + "\"");
    const std::string law = r.string_or("drag_law", "thesis");
    if (law == "thesis")
      w.drag_law = WindSpec::DragLaw::Thesis;
    else if (law == "dalla_valle")
      w.drag_law = WindSpec::DragLaw::DallaValle;
    else if (law == "huo2021")
      w.drag_law = WindSpec::DragLaw::Huo2021;
    else
      r.fail("drag_law",
             "must be \"thesis\" (eqs 4.30-4.31), \"dalla_valle\" or \"huo2021\", found \"" + law + "\"");
    w.u_star = r.number("u_star", Range::non_negative());
    w.kappa = r.number_or("kappa", w.kappa, Range::closed(0.1, 1));
    w.roughness = r.number_or("roughness", 0, Range::non_negative());
    w.bin_height = r.number_or("bin_height", 0, Range::non_negative());
    w.top = r.number_or("top", 0, Range::non_negative());
    w.update_interval = r.number_or("update_interval", w.update_interval, Range::positive());
    w.inertia = r.boolean_or("inertia", w.inertia);
    w.thickness = r.number_or("thickness", 0, Range::non_negative());
    if (r.has("bed_level")) w.bed_level = r.number("bed_level");
    if (w.bin_height > 0 && w.top > 0 && w.top / w.bin_height > 1e6)
      r.fail("top", "more than a million wind bins: raise bin_height or lower top");
    r.finish();
  }

  void check_pairs_exist(const TomlReader& top) {
    if (!s_.effects.has(Effect::normal_contact)) return;
    for (int a : used_materials_)
      for (int b : used_materials_)
        if (a < b && !s_.pair_materials.count({a, b}))
          throw InputError(
              top.where_table(), "material_pairs",
              fmt::format("materials \"{}\" and \"{}\" can touch but no [[material_pairs]] entry with "
                          "between = [\"{}\", \"{}\"] says how",
                          s_.materials[a].name, s_.materials[b].name, s_.materials[a].name,
                          s_.materials[b].name));
  }

  void check_ids() {
    std::set<std::int64_t> ids;
    for (const BodySpec& b : s_.bodies)
      if (!ids.insert(b.id).second)
        throw InputError(b.where, "id", fmt::format("body id {} is used twice", b.id));
    for (const Body3Spec& b : s_.bodies3d)
      if (!ids.insert(b.id).second)
        throw InputError(b.where, "id", fmt::format("body id {} is used twice", b.id));
  }

  // Bodies that start overlapped by more than a tolerance would explode on the first step:
  // a mistake in the scene, not physics, so it is rejected.
  void check_initial_overlaps() {
    check_initial_overlaps3d();
    const auto& B = s_.bodies;
    std::vector<Vec3> centre;
    std::vector<double> radius;
    for (const BodySpec& b : B)
      centre.emplace_back(b.position.x, b.position.y, 0.0), radius.push_back(b.radius);
    for (const auto& [i, j] : overlapping_bounds(centre, radius)) {
      const double allowed = s_.overlap_tolerance * std::min(B[i].radius, B[j].radius);
      const double depth = overlap_depth(B[i], B[j]);
      if (depth > allowed)
        throw InputError(B[j].where, fmt::format("bodies[{}].position", j),
                         fmt::format("overlaps body id {} by {:.4g} (allowed {:.4g} = overlap_tolerance x "
                                     "smaller radius)",
                                     B[i].id, depth, allowed));
    }
  }

  // 3-D: sphere pairs, and every body against the planes (a polyhedron by its vertices). Pairs that
  // involve a polyhedron are not checked here.
  void check_initial_overlaps3d() {
    const auto& B = s_.bodies3d;
    std::vector<Vec3> centre;
    std::vector<double> radius;
    for (const Body3Spec& b : B) centre.push_back(b.position), radius.push_back(b.radius);
    auto pairs = overlapping_bounds(centre, radius);
    // Reported as the all-pairs scan did: the first body j that overlaps an earlier one, and its first i.
    std::sort(pairs.begin(), pairs.end(), [](const auto& p, const auto& q) {
      return p.second != q.second ? p.second < q.second : p.first < q.first;
    });
    auto next = pairs.begin();
    for (size_t j = 0; j < B.size(); ++j) {
      for (; next != pairs.end() && next->second == j; ++next) {
        const size_t i = next->first;
        if (B[i].shape != Body3Spec::Shape::Sphere || B[j].shape != Body3Spec::Shape::Sphere) continue;
        const double depth = B[i].radius + B[j].radius - (B[i].position - B[j].position).norm();
        const double allowed = s_.overlap_tolerance * std::min(B[i].radius, B[j].radius);
        if (depth > allowed)
          throw InputError(
              B[j].where, fmt::format("bodies[{}].position", j),
              fmt::format("overlaps body id {} by {:.4g} (allowed {:.4g})", B[i].id, depth, allowed));
      }
      for (size_t k = 0; k < s_.planes.size(); ++k) {
        const PlaneSpec& p = s_.planes[k];
        const Vec3 point = p.point + p.motion.shift(0);  // where a moving plane starts
        double lowest = 1e300;
        if (B[j].shape == Body3Spec::Shape::Sphere)
          lowest = p.normal.dot(B[j].position - point) - B[j].radius;
        else
          for (const Vec3& v : B[j].hull.vertices)
            lowest = std::min(lowest, p.normal.dot(B[j].position + B[j].orientation * v - point));
        const double allowed = s_.overlap_tolerance * B[j].radius;
        if (-lowest > allowed)
          throw InputError(
              B[j].where, fmt::format("bodies[{}].position", j),
              fmt::format("starts {:.4g} inside walls[{}] (allowed {:.4g})", -lowest, k, allowed));
      }
    }
  }

  static std::vector<Vec2> world_outline(const BodySpec& b) {
    std::vector<Vec2> v;
    for (Vec2 p : b.vertices) v.push_back(b.position + rotate(p, b.angle));
    return v;
  }

  static double overlap_depth(const BodySpec& a, const BodySpec& b) {
    const double centre_gap = norm(a.position - b.position);
    if (centre_gap >= a.radius + b.radius) return 0;
    using S = BodySpec::Shape;
    if (a.shape == S::Disc && b.shape == S::Disc) return a.radius + b.radius - centre_gap;
    if (a.shape == S::Polygon && b.shape == S::Polygon) {
      const auto ov = convex_overlap(world_outline(a), world_outline(b));
      std::vector<Vec2> pts;
      for (const auto& o : ov) pts.push_back(o.p);
      return pts.size() >= 3 ? std::sqrt(std::max(0.0, polygon_mass(pts).area)) : 0;
    }
    const BodySpec& disc = a.shape == S::Disc ? a : b;
    const auto poly = world_outline(a.shape == S::Disc ? b : a);
    if (point_in_convex(disc.position, poly)) return disc.radius;
    double gap = 1e300;
    for (size_t k = 0; k < poly.size(); ++k) {
      const Vec2 p = poly[k], d = poly[(k + 1) % poly.size()] - p;
      const double t = std::clamp(dot(disc.position - p, d) / dot(d, d), 0.0, 1.0);
      gap = std::min(gap, norm(disc.position - (p + d * t)));
    }
    return std::max(0.0, disc.radius - gap);
  }

  const toml::table& root_;
  Scene& s_;
  toml::table empty_;
  std::map<std::string, int> material_index_;
  std::vector<Vec2> raw_vertices_;  // the current polygon's vertices as written
  std::set<int> used_materials_;
};

// Applies one "dotted.key=value" override to the parsed document; the value is read as TOML. A table
// on the key's path that the document lacks is made; returns the first one made ("" if none) and the
// keys its parent already had, so that a misspelt name (--set materials.rok.mu=0.2) is told as such.
struct Made {
  std::string table, siblings;
};
Made apply_override(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const SourceLocation where{"--set " + assignment, 0};
  if (eq == std::string::npos || eq == 0) throw InputError(where, "", "expected key=value");
  std::string key = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  auto trim = [](std::string& s) {
    s.erase(0, s.find_first_not_of(" \t"));
    s.erase(s.find_last_not_of(" \t") + 1);
  };
  trim(key);
  trim(value);
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value, "--set " + assignment);
  } catch (const toml::parse_error&) {
    // A bare word is taken as a string, so --set accuracy.integrator=verlet works unquoted.
    try {
      parsed = toml::parse("v = \"" + value + "\"", "--set " + assignment);
    } catch (const toml::parse_error& e) {
      throw InputError(where, key, "value is not valid TOML: " + std::string(e.description()));
    }
  }
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  toml::node* node = &root;
  Made made;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    if (toml::table* t = node->as_table()) {
      if (!t->contains(p) && made.table.empty()) {
        for (const auto& [k, v] : *t)
          made.siblings += (made.siblings.empty() ? "" : ", ") + std::string(k.str());
        for (size_t j = 0; j <= i; ++j) made.table += (j ? "." : "") + parts[j];
      }
      if (!t->contains(p)) t->insert(p, toml::table{});
      node = t->get(p);
    } else if (toml::array* a = node->as_array()) {
      const bool numeric = !p.empty() && std::all_of(p.begin(), p.end(), ::isdigit);
      if (!numeric || std::stoul(p) >= a->size())
        throw InputError(where, key,
                         fmt::format("\"{}\" is not an index of this {}-element array", p, a->size()));
      node = a->get(std::stoul(p));
    } else {
      throw InputError(where, key, "\"" + p + "\" is not a table");
    }
  }
  toml::table* parent = node->as_table();
  if (!parent) throw InputError(where, key, "the key's parent is not a table");
  parent->insert_or_assign(parts.back(), *parsed.get("v"));
  return made;
}

// "bodies.1.radius" (as typed after --set) -> "bodies[1].radius" (as the reader names keys).
std::string reader_key(std::string key) {
  key.erase(0, key.find_first_not_of(" \t"));
  key.erase(key.find_last_not_of(" \t") + 1);
  std::string out;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) {
    const bool index = !part.empty() && std::all_of(part.begin(), part.end(), ::isdigit);
    out += index ? "[" + part + "]" : (out.empty() ? "" : ".") + part;
  }
  return out;
}

}  // namespace

const Material& Scene::pair(int a, int b) const {
  if (a == b) return materials.at(a);
  return pair_materials.at({std::min(a, b), std::max(a, b)});
}

Scene parse_scene(const std::string& text, const std::string& path,
                  const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError({path, static_cast<int>(e.source().begin.line)}, "", std::string(e.description()));
  }
  std::vector<Made> made;
  for (const std::string& o : overrides) made.push_back(apply_override(root, o));
  Scene s;
  s.path = path;
  s.text = text;
  s.overrides = overrides;
  try {
    SceneReader(root, s).read();
  } catch (const InputError& e) {
    // A value that came from --set is reported against the --set, not the file.
    for (std::size_t k = 0; k < overrides.size(); ++k) {
      const std::string& o = overrides[k];
      if (reader_key(o.substr(0, o.find('='))) == e.key())
        throw InputError({"--set " + o, 0}, e.key(), e.message());
      // A table the --set made is incomplete: the error is most likely a misspelt name.
      const std::string table = reader_key(made[k].table);
      if (!table.empty() && e.key().rfind(table, 0) == 0)
        throw InputError({"--set " + o, 0}, made[k].table,
                         fmt::format("the scene has no {} (beside it: {}), so --set made one, and it is "
                                     "incomplete: {}: {}",
                                     made[k].table, made[k].siblings.empty() ? "nothing" : made[k].siblings,
                                     e.key(), e.message()));
    }
    throw;
  }
  return s;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0}, "", "cannot open the scene file");
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_scene(buf.str(), path, overrides);
}

}  // namespace grainlab
