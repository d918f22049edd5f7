// Suite `single-body`: one body, analytic answers, every engine that supports the scene
// (issue #3 checks 1-4 in 2-D). The incline is a horizontal floor with gravity tilted by theta.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine.hpp"
#include "suites.hpp"

namespace grainlab::validation {

std::unique_ptr<Engine> engine_for(const std::string& name, const std::string& toml,
                                   const std::vector<std::string>& sets) {
  return make_engine(name, parse_scene(toml, "<single-body " + name + ">", sets));
}

namespace {

void free_flight(Report& r, const std::string& eng) {
  const std::string toml = R"toml(
[scene]
duration = 1.0
effects = ["gravity"]
[accuracy]
integrator = "verlet"
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0]
velocity = [100.0, 300.0]
)toml";
  const double exact = 300.0 - 0.5 * kG;
  double err[2];
  const double dts[2] = {1e-3, 5e-4};
  for (int k = 0; k < 2; ++k) {
    auto e = engine_for(eng, toml, {fmt::format("accuracy.dt={}", dts[k])});
    e->advance_to(1.0);
    err[k] = std::abs(e->frame().position[1] - exact);
  }
  const double order = err[1] > 0 ? std::log2(err[0] / err[1]) : INFINITY;
  r.expect_below("free-flight/height-error", eng, err[0], kG * dts[0],
                 fmt::format("|y(1 s) - parabola| at dt = 1e-3 s, below g dt; order in dt: {}",
                             std::isfinite(order) ? fmt::format("{:.2f}", order) : std::string("exact")));
}

}  // namespace

std::string bounce_scene(int dimension, double speed, const std::string& material_line) {
  const bool three = dimension == 3;
  return fmt::format(
      R"toml(
[scene]
dimension = {dim}
duration = 1.0
effects = ["normal_contact"]
[accuracy]
dt = 1e-5
tolerance = 1e-6
[materials.grain]
k_n = 5e6
{material}
[[walls]]
type = "{wall}"
point = {origin}
normal = {up}
[[bodies]]
shape = "{shape}"
radius = 1.0
density = 2.0
position = {start}
velocity = {velocity}
)toml",
      fmt::arg("dim", dimension), fmt::arg("material", material_line),
      fmt::arg("wall", three ? "plane" : "line"),
      fmt::arg("origin", three ? "[0.0, 0.0, 0.0]" : "[0.0, 0.0]"),
      fmt::arg("up", three ? "[0.0, 0.0, 1.0]" : "[0.0, 1.0]"), fmt::arg("shape", three ? "sphere" : "disc"),
      fmt::arg("start", three ? "[0.0, 0.0, 1.05]" : "[0.0, 1.05]"),
      fmt::arg("velocity", three ? fmt::format("[0.0, 0.0, {}]", -speed) : fmt::format("[0.0, {}]", -speed)));
}

double bounce_restitution(const std::string& eng, double speed, const std::string& material_line,
                          int dimension) {
  auto e = engine_for(eng, bounce_scene(dimension, speed, material_line));
  const std::size_t up = dimension - 1;  // y in 2-D, z in 3-D
  const double flight = 0.05 / speed;
  // Until the body leaves the wall; a contact lasts ~4 ms, far longer than the fast flights.
  for (int k = 1; k <= 100000; ++k) {
    e->advance_to(k * flight / 100);
    const Frame f = e->frame();
    if (f.position[up] > 1.0 && f.velocity[up] > 0) return f.velocity[up] / speed;
  }
  return NAN;
}

namespace {

// Downslope acceleration of a body on a floor with gravity tilted by theta (measured between 0.2 and
// 0.6 s, after the contact has settled), and how far it moved.
struct Slide {
  double acceleration = 0, distance = 0;
};
std::optional<Slide> incline(const std::string& eng, const std::string& body, const std::string& effects,
                             double theta_deg, double mu) {
  const double th = theta_deg * M_PI / 180;
  const std::string toml =
      fmt::format(R"toml(
[scene]
duration = 1.0
gravity = [{gx}, {gy}]
effects = [{effects}]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 1e7
restitution = 0.2
k_s = 1e7
damping_s = 3000
mu = {mu}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
{body}
)toml",
                  fmt::arg("gx", kG * std::sin(th)), fmt::arg("gy", -kG * std::cos(th)),
                  fmt::arg("effects", effects), fmt::arg("mu", mu), fmt::arg("body", body));
  std::unique_ptr<Engine> e;
  try {
    e = engine_for(eng, toml);
  } catch (const InputError&) {
    return std::nullopt;  // the engine cannot build this scene (e.g. no polygons): reported as skipped
  }
  e->advance_to(0.2);
  const Frame a = e->frame();
  e->advance_to(0.6);
  const Frame b = e->frame();
  return Slide{(b.velocity[0] - a.velocity[0]) / 0.4, b.position[0] - a.position[0]};
}

const char* kBlock = R"toml([[bodies]]
shape = "polygon"
vertices = [[-2.5, -0.5], [2.5, -0.5], [2.5, 0.5], [-2.5, 0.5]]
density = 2.0
position = [0.0, 0.4995])toml";
const char* kDisc = R"toml([[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.9995])toml";

// Geometric rest height of the die's centre of mass with face k down: the lowest vertex, measured
// from the centre of mass, after rotating the body by k quarter turns.
double die_expected_height(int face) {
  double lowest = 1e9;
  for (Vec2 v : {Vec2{-1, -1}, Vec2{1, -1}, Vec2{1, 1}, Vec2{-1, 1}})
    lowest = std::min(lowest, rotate(v - Vec2{0.3, 0.3}, face * M_PI / 2).y);
  return -lowest;
}

// Centre-of-mass height of a square die (half-side 1 cm, centre of mass moved f = 0.3 of the way to a
// corner) left to settle on a floor with face k down; nullopt if the engine cannot build it.
std::optional<double> die_rest_height(const std::string& eng, int face) {
  const std::string toml =
      fmt::format(R"toml(
[scene]
duration = 1.0
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 1e7
restitution = 0.2
k_s = 1e7
damping_s = 3000
mu = 0.8
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
center_of_mass = [0.3, 0.3]
density = 2.0
position = [0.0, {y}]
angle = {angle}
)toml",
                  fmt::arg("y", die_expected_height(face) + 0.002), fmt::arg("angle", face * M_PI / 2));
  std::unique_ptr<Engine> e;
  try {
    e = engine_for(eng, toml);
  } catch (const InputError&) {
    return std::nullopt;
  }
  e->advance_to(0.5);
  return e->frame().position[1];
}

void checks_for(Report& r, const std::string& eng, std::string& md) {
  free_flight(r, eng);
  for (double v : {1.0, 50.0, 500.0}) {
    const double e = bounce_restitution(eng, v, "restitution = 0.7");
    r.expect_near(
        fmt::format("bounce/restitution/v={}", v), eng, e, 0.7, 0.007,
        "disc on a line; the scene's restitution within 1 % (1 cm/s is below Box2D's default threshold)");
  }
  const std::string sliding = "\"gravity\", \"normal_contact\", \"friction\", \"rotation\"";
  auto text = [](const std::optional<Slide>& s, double analytic) {
    return s ? fmt::format("{:.2f} (analytic {:.2f})", s->acceleration, analytic)
             : std::string("not supported");
  };
  const double a_slide = kG * (std::sin(M_PI / 6) - 0.3 * std::cos(M_PI / 6));
  const auto slide = incline(eng, kBlock, sliding, 30, 0.3);
  if (slide)
    r.expect_near("incline/block-slides", eng, slide->acceleration, a_slide, 0.01 * a_slide,
                  "5 x 1 cm block, 30 deg, mu = 0.3: g (sin - mu cos) within 1 %");
  const auto stick = incline(eng, kBlock, sliding, 20, 0.5);
  if (stick)
    r.expect_below("incline/block-sticks", eng, std::abs(stick->distance), 1e-3,
                   "20 deg, mu = 0.5 > tan 20: moves less than 1e-3 cm in 0.4 s");
  const double a_roll = kG * std::sin(M_PI / 9) / 1.5;
  const auto roll = incline(eng, kDisc, sliding, 20, 0.5);
  if (roll)
    r.expect_near("incline/disc-rolls", eng, roll->acceleration, a_roll, 0.01 * a_roll,
                  "disc, 20 deg, no slip: g sin / (1 + I/m r^2) within 1 %");
  std::vector<double> heights;
  for (int face = 0; face < 4; ++face)
    if (auto h = die_rest_height(eng, face)) heights.push_back(*h);
  std::string die_text = "not supported";
  if (heights.size() == 4) {
    const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
    r.expect_near(
        "loaded-die/rest-energy-spread", eng, *hi - *lo, 0.6, 0.006,
        "square die, centre of mass 0.3 of the way to a corner: high-face minus low-face rest height "
        "= 2 f a = 0.6 cm within 1 % (m g times this is the energy difference)");
    die_text =
        fmt::format("{:.4f} / {:.4f} / {:.4f} / {:.4f}", heights[0], heights[1], heights[2], heights[3]);
  }
  md += fmt::format("| {} | {:.4f} | {} | {} | {} | {} |\n", eng,
                    bounce_restitution(eng, 1.0, "restitution = 0.7"), text(slide, a_slide),
                    stick ? fmt::format("{:.2e}", stick->distance) : std::string("not supported"),
                    text(roll, a_roll), die_text);
}

}  // namespace

void run_single_body_suite(Report& r, const SuiteOptions& o) {
  std::string md =
      "## Single body on every engine\n\n| engine | restitution at 1 cm/s (scene 0.7) | sliding block accel "
      "(cm/s^2) | "
      "sticking block moved (cm) | rolling disc accel (cm/s^2) | loaded die rest heights, faces 0-3 "
      "(geometry: "
      "1.3 / 1.3 / 0.7 / 0.7 cm) |\n|---|---|---|---|---|---|\n";
  for (const std::string& eng : engine_names()) {
    if (o.log) o.log("single body on " + eng);
    checks_for(r, eng, md);
  }
  r.markdown.push_back(md);
  md =
      "## Single body in 3-D\n\n| engine | sphere restitution at 1 cm/s (0.7) | sliding box accel (cm/s^2) | "
      "sticking box moved (cm) | rolling sphere accel (cm/s^2) | loaded cube rest heights, faces +x +y +z -x "
      "-y "
      "-z (geometry 0.8 x 3, 1.2 x 3 cm) | torque-free box |\n|---|---|---|---|---|---|---|\n";
  for (const std::string& eng : engines_for_dimension(3)) {
    if (o.log) o.log("single body in 3-D on " + eng);
    single_body_3d_checks(r, eng, md);
  }
  r.markdown.push_back(md);
}

}  // namespace grainlab::validation
