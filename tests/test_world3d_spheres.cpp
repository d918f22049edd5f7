// The 3-D engine's sphere kernel (world3d_spheres.cpp) against its general path: the same jostling,
// rotating, rubbing pile of spheres in a box must come out the same (to round-off over a short run, in
// which neighbour lists are rebuilt with springs held across the rebuild), and the kernel must be the one
// a sphere bed runs on.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "rng.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {
std::string pile_scene(bool friction) {
  std::string t = fmt::format(R"toml(
[scene]
name = "sphere kernel pile"
dimension = 3
duration = 1.0
effects = ["gravity", "normal_contact", {}"rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.grain]
k_n = 2e5
gamma_n = 40
k_s = 1.5e5
gamma_s = 20
mu = 0.4
)toml",
                              friction ? "\"friction\", " : "");
  Rng rng(11, 0);
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k)
        t += fmt::format(
            "[[bodies]]\nshape = \"sphere\"\nradius = {}\ndensity = 2.65\nposition = [{}, {}, {}]\n"
            "velocity = [{}, {}, {}]\nspin = [{}, {}, {}]\n",
            rng.uniform(0.46, 0.5), 0.5 + 1.0 * i, 0.5 + 1.0 * j, 0.5 + 1.0 * k, rng.uniform(-40, 40),
            rng.uniform(-40, 40), rng.uniform(-40, 40), rng.uniform(-5, 5), rng.uniform(-5, 5),
            rng.uniform(-5, 5));
  const char* planes[5][2] = {{"[0, 0, 0]", "[0, 0, 1]"},
                              {"[0, 0, 0]", "[1, 0, 0]"},
                              {"[5, 0, 0]", "[-1, 0, 0]"},
                              {"[0, 0, 0]", "[0, 1, 0]"},
                              {"[0, 4, 0]", "[0, -1, 0]"}};
  for (const auto& p : planes)
    t += fmt::format("[[walls]]\ntype = \"plane\"\npoint = {}\nnormal = {}\n", p[0], p[1]);
  return t;
}
}  // namespace

TEST(SphereKernel3d, MatchesTheGeneralPathOnAJostlingPile) {
  for (const bool friction : {true, false}) {
    SCOPED_TRACE(friction ? "friction" : "frictionless");
    const Scene scene = parse_scene(pile_scene(friction), "<pile>");
    World3d kernel(scene), general(scene);
    general.use_sphere_kernel(false);
    for (int k = 1; k <= 6; ++k) {  // several calls: the kernel's state goes out to the bodies and back
      kernel.advance_to(k * 100 * 2e-5);
      general.advance_to(k * 100 * 2e-5);
    }
    ASSERT_TRUE(kernel.on_sphere_kernel());
    ASSERT_FALSE(general.on_sphere_kernel());
    EXPECT_GT(kernel.count_contacts(), 20u);
    EXPECT_EQ(kernel.count_contacts(), general.count_contacts());
    double worst = 0;
    for (std::size_t i = 0; i < kernel.bodies().size(); ++i) {
      const Body3 &a = kernel.bodies()[i], &b = general.bodies()[i];
      worst = std::max({worst, (a.x - b.x).norm(), 1e-2 * (a.v - b.v).norm(), 1e-2 * (a.w - b.w).norm()});
    }
    EXPECT_LT(worst, 1e-9);
    const Energies ea = kernel.energies(), eb = general.energies();
    EXPECT_NEAR(ea.elastic, eb.elastic, 1e-9 * std::abs(eb.elastic));
    EXPECT_NEAR(ea.kinetic_rotational, eb.kinetic_rotational, 1e-9 * eb.kinetic_rotational);
  }
}

}  // namespace grainlab::dem
