// Moving planes in 3-D: a floor vibrated sinusoidally, z_p(t) = -A cos(omega t). A grain resting on it
// follows it while the floor's downward acceleration is below g and leaves it where A omega^2 cos(omega t)
// first reaches -g: omega t = arccos(-1 / Gamma), Gamma = A omega^2 / g (120 deg at Gamma = 2). Below
// Gamma = 1 it never leaves. Checked on the sphere kernel (36 spheres apart from each other, the floor
// moving five skins) and on the general path, which must agree; engines that cannot move planes refuse.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "engine.hpp"
#include "input_error.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {

constexpr double kG = 981, kA = 1.0, kR = 1.0, kDt = 1e-4;

double omega(double gamma) {
  return std::sqrt(gamma * kG / kA);
}

// 6 x 6 spheres 3 cm apart resting on the floor at its lowest point (the centre one radius above it).
std::string vibrated_scene(double gamma) {
  std::string t = fmt::format(R"toml(
[scene]
name = "vibrated floor"
dimension = 3
duration = 0.2
effects = ["gravity", "normal_contact"]
[accuracy]
integrator = "verlet"
dt = {}
[materials.grain]
k_n = 1e7
restitution = 0.5
[[walls]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
motion = {{ amplitude = [0, 0, {}], frequency = {}, phase = [0, 0, {}] }}
)toml",
                              kDt, kA, omega(gamma) / (2 * M_PI), -M_PI / 2);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      t +=
          fmt::format("[[bodies]]\nshape = \"sphere\"\nradius = {}\ndensity = 2.65\nposition = [{}, {}, 0]\n",
                      kR, 3.0 * i, 3.0 * j);
  return t;
}

struct Flight {
  double takeoff_phase = NAN;  // omega t at which the first sphere's gap to the floor opened, degrees
  double worst_gap = -1e300;   // the largest gap of any sphere before t_end (cm)
};

// Steps to t_end recording when sphere 0 leaves the floor, and the largest gap of any sphere.
Flight fly(World3d& w, double gamma, double t_end) {
  Flight f;
  const double om = omega(gamma);
  for (double t = kDt; t <= t_end + 1e-12; t += kDt) {
    w.advance_to(t);
    const double floor = -kA * std::cos(om * t);
    for (std::size_t i = 0; i < w.bodies().size(); ++i) {
      const double gap = w.bodies()[i].x.z() - kR - floor;
      f.worst_gap = std::max(f.worst_gap, gap);
      if (i == 0 && gap > 0 && std::isnan(f.takeoff_phase) && t > 0.005)
        f.takeoff_phase = om * t * 180 / M_PI;
    }
  }
  return f;
}

}  // namespace

TEST(MovingPlanes, GrainLeavesAVibratedFloorWhereItsAccelerationPassesG) {
  const Scene scene = parse_scene(vibrated_scene(2.0), "<vibrated>");
  World3d kernel(scene), general(scene);
  general.use_sphere_kernel(false);
  const double t_end = (2 * M_PI / 3 + 0.3) / omega(2.0);  // a little past the take-off
  const Flight a = fly(kernel, 2.0, t_end), b = fly(general, 2.0, t_end);
  ASSERT_TRUE(kernel.on_sphere_kernel());
  // The soft contact unloads over a fraction of its period (3.3 ms, 8 deg of the floor's cycle): a few
  // degrees late.
  EXPECT_NEAR(a.takeoff_phase, 120.0, 5.0);
  EXPECT_NEAR(b.takeoff_phase, 120.0, 5.0);
  for (std::size_t i = 0; i < kernel.bodies().size(); ++i)
    EXPECT_NEAR(kernel.bodies()[i].x.z(), general.bodies()[i].x.z(), 1e-9) << i;
  // The floor moved 2 cm, ten skins: the kernel must have kept it in every sphere's list (all fly alike).
  for (std::size_t i = 1; i < kernel.bodies().size(); ++i)
    EXPECT_NEAR(kernel.bodies()[i].x.z(), kernel.bodies()[0].x.z(), 1e-9) << i;
  EXPECT_GT(kernel.bodies()[0].x.z(), 1.0);  // risen with the floor
}

TEST(MovingPlanes, BelowGammaOneTheGrainsRideTheFloor) {
  const Scene scene = parse_scene(vibrated_scene(0.5), "<vibrated>");
  World3d w(scene);
  const Flight f = fly(w, 0.5, 2 * (2 * M_PI) / omega(0.5));  // two periods
  ASSERT_TRUE(w.on_sphere_kernel());
  EXPECT_TRUE(std::isnan(f.takeoff_phase)) << f.takeoff_phase;
  EXPECT_LT(f.worst_gap, 0.0);  // always pressed into the floor
}

TEST(MovingPlanes, SceneReaderChecksTheMotionAndRigidEnginesRefuseIt) {
  std::string bad = vibrated_scene(2.0);
  bad.replace(bad.find("amplitude = [0, 0, 1]"), 21, "amplitude = [0, 1]");
  EXPECT_THROW(parse_scene(bad, "<bad>"), InputError);
  const Scene scene = parse_scene(vibrated_scene(2.0), "<vibrated>");
  for (const char* engine : {"ode", "bullet"}) {
    try {
      make_engine(engine, scene);
      ADD_FAILURE() << engine << " accepted a moving plane";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("move planes"), std::string::npos) << e.what();
    }
  }
}

}  // namespace grainlab::dem
