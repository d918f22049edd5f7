// "Only the effects a scene calls for": absent effects cost nothing and enabling an effect that cannot
// act changes no result.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "bed_benchmark.hpp"
#include "scene.hpp"
#include "world.hpp"

using namespace grainlab;

namespace {

std::string two_far_discs(const std::string& effects) {
  return fmt::format(R"toml(
[scene]
duration = 0.5
effects = [{}]
[accuracy]
integrator = "predictor-corrector"
[materials.grain]
k_n = 1e6
restitution = 0.5
k_s = 1e6
mu = 0.8
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0]
velocity = [30.0, 10.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [50.0, 0.0]
velocity = [-30.0, 10.0]
)toml",
                     effects);
}

}  // namespace

TEST(Effects, FrictionAndRotationBetweenBodiesThatNeverTouchChangeNothing) {
  dem::World plain(parse_scene(two_far_discs(R"("gravity", "normal_contact")"), "<plain>"));
  dem::World full(
      parse_scene(two_far_discs(R"("gravity", "normal_contact", "friction", "rotation")"), "<full>"));
  plain.advance_to(0.5);
  full.advance_to(0.5);
  for (std::int64_t id : {0, 1}) {
    const long a = plain.index_of(id), b = full.index_of(id);
    EXPECT_EQ(plain.particles().x[a], full.particles().x[b]);  // bit-identical, not just close
    EXPECT_EQ(plain.particles().y[a], full.particles().y[b]);
    EXPECT_EQ(plain.particles().vy[a], full.particles().vy[b]);
  }
  EXPECT_EQ(plain.diagnostics().steps, full.diagnostics().steps);
}

TEST(Effects, FrictionlessBedStoresNoShearHistory) {
  bench::BedOptions o;
  o.nx = 20, o.ny = 5, o.frictionless = true, o.spacing = 2.0, o.first_row = 1.0;
  dem::World frictionless(parse_scene(bench::bed_scene_toml(o), "<bed>"));
  o.frictionless = false;
  dem::World frictional(parse_scene(bench::bed_scene_toml(o), "<bed>"));
  for (int s = 0; s < 200; ++s) frictionless.step(), frictional.step();
  EXPECT_GT(frictionless.count_contacts(), 0u);
  EXPECT_EQ(frictionless.history_entries(), 0u);
  EXPECT_GT(frictional.history_entries(), 0u);
}

namespace {
// A disc on an incline of angle theta, not rotating (so it can only slide).
dem::World disc_on_incline(double theta_deg, double mu, double skin) {
  const double th = theta_deg * M_PI / 180;
  const std::string toml =
      fmt::format(R"toml(
[scene]
duration = 1.0
gravity = [{gx}, {gy}]
effects = ["gravity", "normal_contact", "friction"]
[accuracy]
integrator = "verlet"
dt = 2e-5
skin = {skin}
[materials.grain]
k_n = 1e6
restitution = 0.3
k_s = 1e6
damping_s = 2000
mu = {mu}
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.9939]
)toml",
                  fmt::arg("gx", 981 * std::sin(th)), fmt::arg("gy", -981 * std::cos(th)),
                  fmt::arg("skin", skin), fmt::arg("mu", mu));
  return dem::World(parse_scene(toml, "<incline>"));
}
}  // namespace

TEST(Effects, ShearHistorySurvivesNeighbourRebuilds) {
  // Below the friction angle the disc must stay put; a tiny skin forces a list rebuild every step,
  // so the shear spring must travel through the id-keyed transfer or the disc creeps away.
  for (double skin : {1e-9, 0.2}) {
    dem::World w = disc_on_incline(20, 0.5, skin);
    w.advance_to(0.3);
    const double x1 = w.particles().x[0];
    w.advance_to(1.0);
    EXPECT_LT(std::abs(w.particles().x[0] - x1), 1e-6) << "skin " << skin;
    if (skin < 1e-6) {
      EXPECT_GT(w.diagnostics().neighbor_rebuilds, 1000u);
    }
  }
}

TEST(Effects, SlidingAccelerationMatchesCoulombFriction) {
  const double th = 30 * M_PI / 180, mu = 0.2;
  dem::World w = disc_on_incline(30, mu, 0.2);
  w.advance_to(0.2);
  const double v1 = w.particles().vx[0];
  w.advance_to(0.7);
  const double a = (w.particles().vx[0] - v1) / 0.5;
  const double expected = 981 * (std::sin(th) - mu * std::cos(th));
  EXPECT_NEAR(a, expected, 0.01 * expected);
}
