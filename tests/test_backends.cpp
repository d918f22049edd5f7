// The Engine interface: the same scene on several engines, capabilities enforced with clear messages.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "contact_law.hpp"
#include "engine.hpp"
#include "scene.hpp"
#include "suites.hpp"

using namespace grainlab;

using validation::bounce_restitution;

TEST(Engines, CatalogListsTheEngines) {
  EXPECT_EQ(engine_names(), (std::vector<std::string>{"native", "box2d", "ode", "bullet"}));
}

TEST(Engines, RestitutionIsTheScenesOnEveryEngineAndSpeed) {
  // 1 cm/s is far below Box2D's default restitution threshold (1 m/s), which grainlab switches off.
  for (const char* engine : {"native", "box2d", "ode", "bullet"})
    for (double v : {1.0, 50.0, 500.0}) {
      EXPECT_NEAR(bounce_restitution(engine, v, "restitution = 0.7"), 0.7, 0.007) << engine << " v=" << v;
    }
}

TEST(Engines, SoftContactDampingBecomesEq22RestitutionOnImpulseEngines) {
  // Table 2.1's damping coefficient against a wall: m_eff = m = 2 pi.
  const double expected = dem::restitution_from_damping(5e6, 1000.0, 2 * M_PI);
  EXPECT_NEAR(bounce_restitution("box2d", 100.0, "damping_n = 1000.0"), expected, 0.01 * expected);
  EXPECT_NEAR(bounce_restitution("native", 100.0, "damping_n = 1000.0"), expected, 0.01 * expected);
}

TEST(Engines, UnsupportedSceneNamesTheEngineAndTheCapability) {
  const Scene periodic = parse_scene(R"toml(
[scene]
duration = 1.0
periodic_x = [-50.0, 50.0]
effects = ["gravity"]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0]
)toml",
                                     "<p>");
  try {
    make_engine("box2d", periodic);
    FAIL() << "box2d accepted a periodic scene";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("engine \"box2d\" cannot do periodic boundaries"),
              std::string::npos);
  }
  EXPECT_THROW(make_engine("no-such-engine", periodic), InputError);
}

TEST(Engines, Box2DFreeFlightErrorIsFirstOrderInDt) {
  // Box2D integrates with semi-implicit Euler: after 1 s the height is off by g dt t / 2.
  std::vector<double> errors;
  for (double dt : {1e-2, 5e-3}) {
    const Scene s = parse_scene(R"toml(
[scene]
duration = 1.0
effects = ["gravity"]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0]
)toml",
                                "<flight>", {fmt::format("accuracy.dt={}", dt)});
    auto e = make_engine("box2d", s);
    e->advance_to(1.0);
    errors.push_back(std::abs(e->frame().position[1] - (-0.5 * 981.0)));
    EXPECT_NEAR(errors.back(), 0.5 * 981.0 * dt, 0.05 * 981.0 * dt);
  }
  EXPECT_NEAR(std::log2(errors[0] / errors[1]), 1.0, 0.1);
}

TEST(Engines, SingleBodySuitePassesOnEveryEngine) {
  validation::Report r;
  validation::run_single_body_suite(r, {});
  for (const auto& c : r.checks) EXPECT_TRUE(c.passed) << c.id << " on " << c.engine << ": " << c.value;
  // Every engine gets free flight, three bounces and the rolling disc; the block needs polygons.
  EXPECT_GE(r.checks.size(), 5 * engine_names().size());
}

TEST(Engines, DiscRidesAShakenFloorOnEveryEngine) {
  // Floor shaken vertically at 12 Hz with 0.15 cm amplitude: peak acceleration 853 cm/s^2 < g, so a
  // resting disc never leaves it and its centre stays one radius above the floor.
  const Scene scene = parse_scene(R"toml(
[scene]
duration = 0.5
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 1e7
restitution = 0.2
k_s = 1e7
damping_s = 3000
mu = 0.5
[[walls]]
from = [-20.0, 0.0]
to = [20.0, 0.0]
motion = { amplitude = [0.0, 0.15], frequency = 12.0 }
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.9995]
)toml",
                                  "<shaken floor>");
  for (const std::string& eng : engine_names()) {
    auto e = make_engine(eng, scene);
    double lo = 1e9, hi = -1e9;
    for (int k = 1; k <= 50; ++k) {
      const double t = k * 0.01;
      e->advance_to(t);
      const double gap = e->frame().position[1] - 0.15 * std::sin(2 * M_PI * 12.0 * t);
      lo = std::min(lo, gap), hi = std::max(hi, gap);
    }
    // The centre rides one radius above the floor. Impulse engines rest on a skin (Box2D's edge
    // radius: 0.02 cm here), so the gap is tested for constancy, and its level to 3 %.
    EXPECT_LT(hi - lo, 0.01) << eng;
    EXPECT_NEAR(lo, 1.0, 0.03) << eng;
  }
}
