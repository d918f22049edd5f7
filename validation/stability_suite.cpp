// Suite `stability`: hard cases on every engine that supports them. Each run is watched for a finite
// state, no energy gain beyond a tolerance, penetration below 5 % of the smaller radius, no tunnelling,
// and termination. The native engine must pass every case; a third-party engine's failure is recorded
// as a documented limitation with the measurement that shows it.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "engine.hpp"
#include "pair_impact.hpp"
#include "polyhedron.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

constexpr double kEnergyTolerance = 1e-3;   // of the energy the run has to move around
constexpr double kPenetrationLimit = 0.05;  // of the smaller radius

struct Case {
  std::string name, description;
  int dimension = 2;
  std::string toml;
  double duration = 0, sample = 0;
  // Per-engine settings (the impulse engines need other steps than the native one).
  std::vector<std::string> native_sets, impulse_sets;
  // True when the bodies are where they can only be by passing through each other or the floor.
  std::function<bool(const Frame&)> tunnelled;
  bool floor = true;                             // the floor y = 0 counts for penetration
  double penetration_limit = kPenetrationLimit;  // of the smaller radius
  std::string penetration_note = {};             // why a case has another limit
  double energy_floor = 0;                       // erg: the smallest energy scale (cases that start at rest)
  double rest_after = 0;  // > 0: from this time the bodies must be at rest and stay there (a pile)
};

struct Watch {
  bool finite = true, tunnelled = false, terminated = false;
  double energy_gain = 0;  // (largest total - initial total) / energy scale
  double penetration = 0;  // largest overlap / smaller radius (discs and spheres, and the floor)
  double seconds = 0;
  std::string error;  // what stopped the run, if it stopped
  // Piles: kinetic energy after rest_after / the energy moved around, and how far the bodies crept
  // between rest_after and the end (mean displacement / mean radius).
  double late_kinetic = 0, creep = 0;
};

bool all_finite(const Frame& f) {
  for (const auto* v : {&f.position, &f.velocity, &f.angular_velocity})
    for (double x : *v)
      if (!std::isfinite(x)) return false;
  return true;
}

// Largest overlap of round bodies (pairs, and each with the floor y = 0 or z = 0 if there is one) over
// the smaller radius.
double penetration(const Frame& f, int dimension, bool floor) {
  const std::size_t n = f.radius.size(), up = dimension == 3 ? 2 : 1;
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (f.shape[i] != -1) continue;
    if (floor) worst = std::max(worst, (f.radius[i] - f.position[3 * i + up]) / f.radius[i]);
    for (std::size_t j = i + 1; j < n; ++j) {
      if (f.shape[j] != -1) continue;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += std::pow(f.position[3 * i + k] - f.position[3 * j + k], 2);
      const double overlap = f.radius[i] + f.radius[j] - std::sqrt(d2);
      if (overlap > 0) worst = std::max(worst, overlap / std::min(f.radius[i], f.radius[j]));
    }
  }
  return worst;
}

Watch watch(const Case& c, const std::string& engine) {
  Watch w;
  const auto start = std::chrono::steady_clock::now();
  try {
    const auto sets = engine_capabilities(engine).soft_contacts ? c.native_sets : c.impulse_sets;
    auto e = engine_for(engine, c.toml, sets);
    // Mechanical energy (kinetic + gravitational): stored spring energy is left out, so a contact in
    // progress can only lower it and a rise is a real gain (and the engines are measured alike: the
    // impulse engines store none).
    auto mechanical = [](const EnergyReport& er) { return er.total() - er.elastic; };
    const EnergyReport start_energy = e->energies();
    const double e0 = mechanical(start_energy);
    double e_max = e0, e_min = e0,
           kinetic_max = start_energy.kinetic_translational + start_energy.kinetic_rotational,
           late_kinetic = 0;
    std::optional<Frame> at_rest;  // the frame at rest_after
    for (double t = c.sample; t < c.duration + 0.5 * c.sample; t += c.sample) {
      e->advance_to(std::min(t, c.duration));
      const Frame f = e->frame();
      w.finite &= all_finite(f);
      if (!w.finite) break;
      const double en = mechanical(e->energies());
      e_max = std::max(e_max, en), e_min = std::min(e_min, en);
      w.penetration = std::max(w.penetration, penetration(f, c.dimension, c.floor));
      const EnergyReport er = e->energies();
      kinetic_max = std::max(kinetic_max, er.kinetic_translational + er.kinetic_rotational);
      if (c.tunnelled) w.tunnelled |= c.tunnelled(f);
      if (c.rest_after > 0 && t >= c.rest_after - 1e-12) {
        late_kinetic = std::max(late_kinetic, er.kinetic_translational + er.kinetic_rotational);
        if (!at_rest) at_rest = f;
        double moved = 0, radii = 0;
        for (std::size_t i = 0; i < f.radius.size(); ++i) {
          for (int k = 0; k < 3; ++k) moved += std::abs(f.position[3 * i + k] - at_rest->position[3 * i + k]);
          radii += f.radius[i];
        }
        w.creep = std::max(w.creep, moved / std::max(radii, 1e-300));
      }
    }
    // The energy the run moves around: what it lost from the start to its lowest state, or the most
    // kinetic energy it had (an elastic bounce loses nothing); at least the case's stated floor.
    const double scale = std::max({e0 - e_min, kinetic_max, c.energy_floor});
    w.energy_gain = (e_max - e0) / scale;
    w.late_kinetic = late_kinetic / scale;
    w.terminated = true;
  } catch (const std::exception& ex) {
    w.error = ex.what();
  }
  w.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return w;
}

std::string pair_toml(double k, double e, double speed, double r_left, double r_right, double density_right,
                      double mu = 0.0) {
  return fmt::format(R"toml(
[scene]
duration = 1.0
gravity = [0.0, 0.0]
effects = ["normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-6
[materials.m]
k_n = {k}
restitution = {e}
k_s = {k}
mu = {mu}
[[bodies]]
radius = {rl}
density = 2.0
position = [{xl}, 0.0]
velocity = [{v}, 0.0]
[[bodies]]
radius = {rr}
density = {dr}
position = [{xr}, 0.0]
velocity = [{mv}, 0.0]
)toml",
                     fmt::arg("k", k), fmt::arg("e", e), fmt::arg("mu", mu), fmt::arg("rl", r_left),
                     fmt::arg("xl", -r_left - 0.01), fmt::arg("v", speed), fmt::arg("rr", r_right),
                     fmt::arg("dr", density_right), fmt::arg("xr", r_right + 0.01), fmt::arg("mv", -speed));
}

// Mass of a disc of radius r and 2-D density rho (g/cm^2), as the scene reader makes it.
double disc_mass(double r, double rho) {
  return rho * M_PI * r * r;
}

// Two bodies that must stay in their left-right order.
bool swapped(const Frame& f) {
  return f.position[0] > f.position[3];
}
bool below_floor(const Frame& f, int dimension) {
  const std::size_t up = dimension == 3 ? 2 : 1;
  for (std::size_t i = 0; i < f.radius.size(); ++i)
    if (f.position[3 * i + up] < 0) return true;
  return false;
}

std::string floor_header(double duration, double k, double e, double mu, const std::string& dt) {
  return fmt::format(R"toml(
[scene]
duration = {d}
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = {dt}
[materials.m]
k_n = {k}
restitution = {e}
k_s = {k}
mu = {mu}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
)toml",
                     fmt::arg("d", duration), fmt::arg("dt", dt), fmt::arg("k", k), fmt::arg("e", e),
                     fmt::arg("mu", mu));
}

Case pile_case(int count, double duration) {
  // k_n = 1e8: the pour's hardest landings (about 190 cm/s) overlap under 5 % of a radius.
  std::string toml = floor_header(duration, 1e8, 0.3, 0.5, "1e-5") + R"toml(
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [1.0, 0.0]
[[walls]]
type = "line"
point = [40.0, 0.0]
normal = [-1.0, 0.0]
[[assemblies]]
type = "lattice"
)toml";
  const int per_row = 30;
  toml += fmt::format(R"toml(nx = {}
ny = {}
spacing = 1.3
origin = [1.0, 1.0]
density = 2.0
[assemblies.radius_distribution]
kind = "uniform"
min = 0.4
max = 0.6
)toml",
                      per_row, (count + per_row - 1) / per_row);
  Case c{"pile-at-rest",
         fmt::format(
             "{} discs (r 0.4-0.6) dropped from a loose lattice into a 40 cm box, left {} s: at rest from "
             "{} s on",
             per_row * ((count + per_row - 1) / per_row), duration, duration / 2),
         2,
         toml,
         duration,
         0.05,
         {"accuracy.dt=1e-5"},
         {"accuracy.dt=2e-4"},
         [](const Frame& f) { return below_floor(f, 2); }};
  c.rest_after = 2 * duration / 3;
  return c;
}

// A pile of spheres (radii 0.4-0.6 cm) dropped from a loose seeded grid into a 13.5 x 13.5 cm box.
Case pile3d_case(int count, double duration) {
  std::string toml = fmt::format(R"toml(
[scene]
dimension = 3
duration = {d}
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 1e8
restitution = 0.3
k_s = 1e8
mu = 0.5
)toml",
                                 fmt::arg("d", duration));
  for (const char* wall : {"[0.0, 0.0, 0.0], [0.0, 0.0, 1.0]", "[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]",
                           "[13.5, 0.0, 0.0], [-1.0, 0.0, 0.0]", "[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]",
                           "[0.0, 13.5, 0.0], [0.0, -1.0, 0.0]"}) {
    const std::string w(wall);
    const auto comma = w.find("], [");
    toml += fmt::format("[[walls]]\ntype = \"plane\"\npoint = {}]\nnormal = [{}\n", w.substr(0, comma),
                        w.substr(comma + 4));
  }
  Rng rng(2026);
  for (int k = 0; k < count; ++k)
    toml += fmt::format("[[bodies]]\nradius = {:.6f}\ndensity = 2.0\nposition = [{:.4f}, {:.4f}, {:.4f}]\n",
                        rng.uniform(0.4, 0.6), 0.75 + 1.3 * (k % 10), 0.75 + 1.3 * (k / 10 % 10),
                        1.0 + 1.3 * (k / 100));
  Case c{"pile-3d-at-rest",
         fmt::format("{} spheres (r 0.4-0.6) dropped from a loose grid into a 13.5 x 13.5 cm box, left {} s: "
                     "at rest from "
                     "{:.3g} s on",
                     count, duration, 2 * duration / 3),
         3,
         toml,
         duration,
         0.05,
         {"accuracy.dt=1e-5"},
         {"accuracy.dt=2e-4"},
         [](const Frame& f) { return below_floor(f, 3); }};
  c.rest_after = 2 * duration / 3;
  return c;
}

Case die3d_case(const std::string& name, const std::string& description, const Quat& q) {
  const std::string toml = fmt::format(R"toml(
[scene]
dimension = 3
duration = 1.0
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.m]
k_n = 1e8
restitution = 0.5
k_s = 1e8
mu = 0.8
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[bodies]]
shape = "box"
size = [2.0, 2.0, 2.0]
density = 2.0
position = [0.0, 0.0, 3.0]
orientation = [{:.17g}, {:.17g}, {:.17g}, {:.17g}]
)toml",
                                       q.w(), q.x(), q.y(), q.z());
  return {
      name, description, 3, toml, 1.0, 1e-3, {"accuracy.dt=2e-5"}, {"accuracy.dt=5e-4"}, [](const Frame& f) {
        return below_floor(f, 3);
      }};
}

// A 2 x 2 cm square body (TOML) at (x, y), turned by `angle`.
std::string square_at(double x, double y, double angle = 0) {
  return fmt::format(R"toml(
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [{}, {}]
angle = {:.17g}
)toml",
                     x, y, angle);
}

// A 2-D case on the floor line y = 0 (k 1e8; native steps 1e-5 s, impulse engines 1e-4 s).
Case floor_case(std::string name, std::string description, double duration, double restitution, double mu,
                const std::string& bodies, std::function<bool(const Frame&)> tunnelled) {
  return {std::move(name),
          std::move(description),
          2,
          floor_header(duration, 1e8, restitution, mu, "1e-5") + bodies,
          duration,
          1e-3,
          {"accuracy.dt=1e-5"},
          {"accuracy.dt=1e-4"},
          std::move(tunnelled)};
}

std::vector<Case> cases(bool quick) {
  std::vector<Case> out;
  auto two_d = [](const Frame& f) { return below_floor(f, 2); };
  // Stiff: 100 x the Ch. III spring (6e11 dyn/cm), head-on at 1000 cm/s each: contact 7 microseconds.
  out.push_back({"stiff-contact",
                 "two discs, k = 6e11 dyn/cm (100 x Ch. III), e 0.85, 1000 cm/s each, head-on",
                 2,
                 pair_toml(6e11, 0.85, 1000, 1, 1, 2),
                 2e-4,
                 1e-6,
                 {"accuracy.dt=1e-7"},
                 {"accuracy.dt=1e-6"},
                 swapped});
  out.back().floor = false;  // no floor: the pair floats in zero gravity
  // Soft: Table 2.1's spring (5e6 dyn/cm, 1200 x softer than Ch. III) at 10 cm/s.
  out.push_back({"soft-contact",
                 "two discs, k = 5e6 dyn/cm (Table 2.1), e 0.85, 10 cm/s each, head-on",
                 2,
                 pair_toml(5e6, 0.85, 10, 1, 1, 2),
                 0.01,
                 1e-4,
                 {"accuracy.dt=1e-5"},
                 {"accuracy.dt=1e-4"},
                 swapped});
  out.back().floor = false;  // no floor: the pair floats in zero gravity
  // Mass ratio 1:1000 head-on, and resting in contact.
  out.push_back({"mass-ratio-impact",
                 "a disc hitting one 1000 x heavier (density 2000), 100 cm/s each",
                 2,
                 pair_toml(6e9, 0.85, 100, 1, 1, 2000),
                 1e-3,
                 1e-5,
                 {"accuracy.dt=1e-7"},
                 {"accuracy.dt=1e-5"},
                 swapped});
  out.back().floor = false;  // no floor: the pair floats in zero gravity
  out.push_back({"mass-ratio-stack",
                 "a 1000 x heavier disc resting on a light one on the floor (k 6e9), 0.5 s",
                 2,
                 floor_header(0.5, 6e9, 0.5, 0.5, "1e-6") + R"toml(
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 1.0]
[[bodies]]
radius = 1.0
density = 2000.0
position = [0.0, 3.0]
)toml",
                 0.5,
                 0.01,
                 {"accuracy.dt=2e-7"},
                 {"accuracy.dt=1e-4"},
                 [](const Frame& f) { return below_floor(f, 2) || f.position[4] < f.position[1]; }});
  out.back().energy_floor = disc_mass(1.0, 2000.0) * kG * 1.0;  // the heavy disc lifted by its radius
  // A 1 cm grain dropped onto a 100 cm polygon resting on the floor.
  out.push_back({"grain-on-big-polygon",
                 "a r = 0.5 cm grain dropped 10 cm onto a 100 x 20 cm block on the floor",
                 2,
                 floor_header(0.5, 1e8, 0.7, 0.5, "1e-5") + R"toml(
[[bodies]]
shape = "polygon"
vertices = [[-50.0, -10.0], [50.0, -10.0], [50.0, 10.0], [-50.0, 10.0]]
density = 2.0
position = [0.0, 10.0]
[[bodies]]
radius = 0.5
density = 2.0
position = [3.0, 30.5]
)toml",
                 0.5,
                 1e-3,
                 {"accuracy.dt=2e-6"},
                 {"accuracy.dt=1e-4"},
                 [](const Frame& f) { return f.position[4] < 20.0; }});
  // Polygons meeting vertex on vertex and edge on edge, and a die landing exactly on a corner.
  const double corner = M_PI / 4;
  out.push_back(floor_case("vertex-on-vertex",
                           "a square dropped corner-first onto the corner of a square on the floor", 1.0, 0.5,
                           0.5, square_at(0, 1) + square_at(1, 4.5, corner), two_d));
  out.push_back(floor_case("edge-on-edge", "a square dropped flat onto a square on the floor", 1.0, 0.5, 0.5,
                           square_at(0, 1) + square_at(0, 5),
                           [](const Frame& f) { return f.position[4] < f.position[1]; }));
  out.push_back(floor_case("die-on-corner", "a 2-D die dropped exactly onto a corner (45 deg, no spin)", 1.0,
                           0.5, 0.8, square_at(0, 3, corner), two_d));
  // Restitution 1 (energy must not grow over many bounces), 0, and zero friction.
  const std::string ball = R"toml(
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 6.0]
velocity = [30.0, 0.0]
)toml";
  out.push_back(floor_case("restitution-1",
                           "a disc bouncing on the floor with restitution 1 for 3 s (about 7 bounces)",
                           quick ? 1.0 : 3.0, 1.0, 0.0, ball, two_d));
  out.push_back(floor_case("restitution-0",
                           "a disc dropped on the floor with restitution 0 (critical damping)", 1.0, 0.0, 0.0,
                           ball, two_d));
  out.push_back(floor_case("zero-friction", "a disc sliding and bouncing with mu = 0 and restitution 0.5",
                           1.0, 0.5, 0.0, ball, two_d));
  // A small grain into a bed of 384 discs at 8100 cm/s (Ch. III CASE I). Its penetration limit is the
  // linear contact's own largest overlap at that speed, undamped: v sqrt(m_eff / k).
  const double m_grain = disc_mass(0.5, 2.0), m_bed = disc_mass(1.0, 2.0);
  const double case_i_overlap = 8100 * std::sqrt(m_grain * m_bed / (m_grain + m_bed) / 6e9);
  out.push_back({"case-i-impact",
                 "a r = 0.5 cm grain at 8100 cm/s, 14 deg below horizontal, into 384 discs (k 6e9)",
                 2,
                 floor_header(quick ? 1e-3 : 3e-3, 6e9, 0.85, 0.5, "5e-7") + R"toml(
[[assemblies]]
type = "lattice"
nx = 24
ny = 16
spacing = 2.0
origin = [1.0, 1.0]
radius = 1.0
density = 2.0
[[bodies]]
id = 1000
radius = 0.5
density = 2.0
position = [20.0, 33.0]
velocity = [7859.0, -1960.0]
)toml",
                 quick ? 1e-3 : 3e-3,
                 2.5e-5,
                 {"accuracy.dt=5e-7"},
                 {"accuracy.dt=2e-6"},
                 two_d});
  out.back().penetration_limit = case_i_overlap / 0.5;
  out.back().penetration_note =
      fmt::format("the linear contact's own maximum at 8100 cm/s, v sqrt(m_eff/k) = {:.3f} cm = {:.3f} r",
                  case_i_overlap, case_i_overlap / 0.5);
  // A pile of discs poured from a loose lattice (radii 0.4-0.6 cm, 40 cm box) left to rest.
  out.push_back(pile_case(quick ? 300 : 2000, quick ? 3.0 : 10.0));
  out.push_back(pile3d_case(quick ? 100 : 1000, quick ? 3.0 : 10.0));
  // The 3-D die dropped exactly onto a corner and onto an edge (native, ODE, Bullet).
  const double s3 = 1 / std::sqrt(3.0);
  out.push_back(die3d_case("die-3d-on-corner",
                           "a 2 cm cube dropped from 3 cm exactly onto a corner (body diagonal "
                           "vertical)",
                           Quat::FromTwoVectors(Vec3(s3, s3, s3), Vec3(0, 0, -1))));
  out.push_back(die3d_case("die-3d-on-edge", "a 2 cm cube dropped from 3 cm exactly onto an edge (45 deg)",
                           Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitX()))));
  return out;
}

// Kinetic energy after / before a sphere (r = 1, density 2) hits the plane z = 0 at 1000 cm/s, `angle`
// from the normal (Ch. III contact: k 6e9, e 0.85, mu 0.5; no gravity).
double sphere_on_plane(const std::string& engine, double angle_deg) {
  const double a = angle_deg * M_PI / 180, v = 1000, lead = 1e-3;
  const double duration = lead / (v * std::cos(a)) + 5 * M_PI * std::sqrt(2 * 4.0 / 3 * M_PI / 6e9);
  const std::string toml = fmt::format(R"toml(
[scene]
dimension = 3
duration = {d:.17g}
gravity = [0.0, 0.0, 0.0]
effects = ["normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-7
[materials.m]
k_n = 6e9
restitution = 0.85
k_s = 6e9
mu = 0.5
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0, {z:.17g}]
velocity = [{vx:.17g}, 0.0, {vz:.17g}]
)toml",
                                       fmt::arg("d", duration), fmt::arg("z", 1 + lead),
                                       fmt::arg("vx", v * std::sin(a)), fmt::arg("vz", -v * std::cos(a)));
  const std::vector<std::string> sets = engine_capabilities(engine).soft_contacts
                                            ? std::vector<std::string>{}
                                            : std::vector<std::string>{"accuracy.dt=1e-6"};
  auto e = engine_for(engine, toml, sets);
  auto kinetic = [](const EnergyReport& er) { return er.kinetic_translational + er.kinetic_rotational; };
  const double before = kinetic(e->energies());
  e->advance_to(duration);
  return kinetic(e->energies()) / before;
}

void grazing_impacts(Report& r, std::string& md) {
  // Disc on disc and sphere on sphere at mu 0.5 from 5 to 89 deg: kinetic energy after <= before.
  md +=
      "\n### Grazing frictional impacts\n\nKinetic energy after / before an impact of two grains at 1000 "
      "cm/s "
      "(mu 0.5, e 0.85), and of a sphere hitting the plane, worst over 5-89 deg:\n\n| engine | discs | "
      "spheres | "
      "sphere on plane |\n|---|---|---|---|\n";
  for (const std::string& eng : engine_names()) {
    std::string row = "| " + eng + " |";
    for (int dim : {2, 3}) {
      const auto engines = engines_for_dimension(dim);
      if (std::find(engines.begin(), engines.end(), eng) == engines.end()) {
        row += " - |";
        continue;
      }
      double worst = 0;
      int at = 0;
      for (int a : {5, 15, 30, 45, 60, 75, 85, 89}) {
        const double ratio = pair_impact(eng, dim, 1000.0, a).kinetic_ratio;
        if (ratio > worst) worst = ratio, at = a;
      }
      row += fmt::format(" {:.4f} (at {} deg) |", worst, at);
      Check& c =
          r.expect_below(fmt::format("stability/grazing-impact/{}d", dim), eng, worst, 1.0 + kEnergyTolerance,
                         fmt::format("largest kinetic energy after / before over 5-89 deg (at {} deg)", at));
      if (!c.passed)
        c.known_limitation(
            fmt::format("gains kinetic energy in a grazing impact: {:.4f} at {} deg", worst, at));
    }
    if (eng == "box2d") {
      row += " - |";
    } else {
      double worst = 0;
      int at = 0;
      for (int a : {5, 15, 30, 45, 60, 75, 85, 89}) {
        const double ratio = sphere_on_plane(eng, a);
        if (ratio > worst) worst = ratio, at = a;
      }
      row += fmt::format(" {:.4f} (at {} deg) |", worst, at);
      Check& c =
          r.expect_below("stability/grazing-impact/sphere-on-plane", eng, worst, 1.0 + kEnergyTolerance,
                         fmt::format("largest kinetic energy after / before over 5-89 deg (at {} deg)", at));
      if (!c.passed)
        c.known_limitation(
            fmt::format("gains kinetic energy in a grazing impact: {:.4f} at {} deg", worst, at));
    }
    md += row + "\n";
  }
}

void adaptive_underflow(Report& r, std::string& md) {
  // A tolerance no step can meet: the run must stop with a message naming dt_min, not stall.
  const auto start = std::chrono::steady_clock::now();
  std::string message;
  try {
    auto e = engine_for(
        "native", pair_toml(5e6, 0.7, 50, 1, 1, 2),
        {"accuracy.integrator=\"predictor-corrector\"", "accuracy.tolerance=1e-15", "accuracy.dt_min=1e-9"});
    e->advance_to(0.01);
  } catch (const std::exception& ex) {
    message = ex.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool clear = message.find("dt_min") != std::string::npos;
  r.expect_below(
      "stability/adaptive-underflow-stops", "native", clear ? seconds : 1e9, 10.0,
      "seconds until a predictor-corrector run with tolerance 1e-15 and dt_min 1e-9 stops with a message "
      "naming dt_min: " +
          (message.empty() ? std::string("it did not stop") : message));
  md += fmt::format(
      "\n### Adaptive step underflow\n\nnative, predictor-corrector, tolerance 1e-15, dt_min 1e-9: {} "
      "after {:.2f} s:\n\n> {}\n",
      clear ? "stops" : "DOES NOT stop clearly", seconds, message);
}

}  // namespace

void run_stability_suite(Report& r, const SuiteOptions& o) {
  std::string md =
      "## Stability (suite `stability`)\n\nHard cases on every engine that supports them. A run passes if "
      "its "
      "state stays finite, its mechanical energy (kinetic + gravitational) never rises above the start by "
      "more than 1e-3 of the energy it "
      "moves around, no two round bodies (or a round body and the floor) overlap by more than 5 % of the "
      "smaller radius, nothing tunnels (each case states what that means) and it terminates. The native "
      "engine must pass every case; an impulse engine's failure is a documented limitation.\n\n"
      "| case | engine | verdict | finite | energy gain | penetration | tunnelled | seconds |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const Case& c : cases(o.quick)) {
    for (const std::string& eng : engines_for_dimension(c.dimension)) {
      const Watch w = watch(c, eng);
      // A pile must come to rest (kinetic energy below 1e-6 of what it moved around) and stay (creep
      // below 1 % of a radius on average).
      const bool rests = c.rest_after <= 0 || (w.late_kinetic <= 1e-6 && w.creep <= 0.01);
      const bool ok = w.terminated && w.finite && w.energy_gain <= kEnergyTolerance &&
                      w.penetration <= c.penetration_limit && !w.tunnelled && rests;
      std::string what;
      if (!w.terminated) what = "stopped: " + w.error;
      if (!w.finite) what += " non-finite state;";
      if (w.energy_gain > kEnergyTolerance)
        what += fmt::format(" energy rose by {:.3g} of its scale;", w.energy_gain);
      if (w.penetration > kPenetrationLimit)
        what += fmt::format(" overlap {:.3g} of the smaller radius (limit {:.3g});", w.penetration,
                            c.penetration_limit);
      if (w.tunnelled) what += " tunnelled;";
      if (!rests)
        what += fmt::format(" not at rest: kinetic energy {:.3g} of its scale after {} s, creep {:.3g} r;",
                            w.late_kinetic, c.rest_after, w.creep);
      Check& chk = r.expect_below("stability/" + c.name, eng, ok ? 0.0 : 1.0, 0.0,
                                  c.description + (ok ? std::string("") : ": " + what));
      if (!ok) chk.known_limitation(c.description + ":" + what);
      md += fmt::format("| {} | {} | {} | {} | {:.2e} | {:.3f} | {} | {:.2f} |\n", c.name, eng,
                        ok ? "pass" : "FAIL", w.finite ? "yes" : "NO", w.energy_gain, w.penetration,
                        w.tunnelled ? "YES" : "no", w.seconds);
      if (o.log) o.log(fmt::format("stability {} on {}: {}{}", c.name, eng, ok ? "pass" : "FAIL", what));
    }
  }
  md += "\nPenetration limits other than 5 %:\n\n";
  for (const Case& c : cases(o.quick))
    if (!c.penetration_note.empty()) md += fmt::format("- {}: {}\n", c.name, c.penetration_note);
  grazing_impacts(r, md);
  adaptive_underflow(r, md);
  r.markdown.push_back(md);
}

}  // namespace grainlab::validation
