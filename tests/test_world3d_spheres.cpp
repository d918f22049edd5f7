// The 3-D engine's sphere kernel (sphere_bed.*) against its general path: the same jostling, rotating,
// rubbing pile of spheres in a box must come out the same (to round-off over a short run, in which
// neighbour lists are rebuilt with springs held across the rebuild), and the kernel must be the one a
// sphere bed runs on. Its two ways of stepping (one sweep, or two passes with ghosts in between) agree
// bit for bit.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "rng.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {
// The steps and the grains' material, shared by the scenes below.
constexpr const char* kVerletGrain = R"toml(
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.grain]
k_n = 2e5
gamma_n = 40
k_s = 1.5e5
gamma_s = 20
mu = 0.4
)toml";

std::string pile_scene(bool friction) {
  std::string t = fmt::format(R"toml(
[scene]
name = "sphere kernel pile"
dimension = 3
duration = 1.0
effects = ["gravity", "normal_contact", {}"rotation"]
{})toml",
                              friction ? "\"friction\", " : "", kVerletGrain);
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

// Spheres far apart, resting on the floor: no pair is near another, and all of the stored energy is in
// the floor contacts, which the kernel must count as the general path does.
TEST(SphereKernel3d, CountsFloorEnergyWithNoPairsNear) {
  std::string t = fmt::format(R"toml(
[scene]
name = "sparse spheres on a floor"
dimension = 3
duration = 1.0
effects = ["gravity", "normal_contact", "friction", "rotation"]
{}[[walls]]
type = "plane"
point = [0, 0, 0]
normal = [0, 0, 1]
)toml",
                              kVerletGrain);
  for (int k = 0; k < 40; ++k)
    t += fmt::format(
        "[[bodies]]\nshape = \"sphere\"\nradius = 0.5\ndensity = 2.65\nposition = [{}, {}, 0.5]\n"
        "velocity = [3, 0, 0]\n",
        5.0 * (k % 8), 5.0 * (k / 8));
  const Scene scene = parse_scene(t, "<sparse>");
  World3d kernel(scene), general(scene);
  general.use_sphere_kernel(false);
  kernel.advance_to(0.01), general.advance_to(0.01);
  ASSERT_TRUE(kernel.on_sphere_kernel());
  EXPECT_EQ(kernel.count_contacts(), 40u);
  const double ea = kernel.energies().elastic, eb = general.energies().elastic;
  EXPECT_GT(eb, 0);
  EXPECT_NEAR(ea, eb, 1e-9 * eb);
}

}  // namespace grainlab::dem

namespace grainlab::dem {

namespace {
// Two spheres head on at x0 - 0.6 and x0 + 0.6 (wrapped into [0, 20)), and 32 still spectators in two
// rows, in a box periodic in x and y; no gravity.
std::string periodic_scene(double x0) {
  std::string t = R"toml(
[scene]
name = "periodic pair"
dimension = 3
duration = 1.0
periodic_x = [0, 20]
periodic_y = [0, 12]
gravity = [0, 0, 0]
effects = ["normal_contact", "friction", "rotation"]
)toml" + std::string(kVerletGrain);
  auto sphere = [&](double x, double y, double vx) {
    t += fmt::format(
        "[[bodies]]\nshape = \"sphere\"\nradius = 0.5\ndensity = 2.65\nposition = [{}, {}, 5]\nvelocity = "
        "[{}, "
        "3, 0]\n",
        x - 20 * std::floor(x / 20), y, vx);
  };
  sphere(x0 - 0.6, 6, 50);
  sphere(x0 + 0.6, 6.2, -50);
  for (int k = 0; k < 16; ++k) sphere(0.6 + 1.2 * k, 2, 0), sphere(0.6 + 1.2 * k, 10, 0);
  return t;
}
}  // namespace

// A collision through the periodic side is the same collision as in the middle of the box, and momentum
// is kept; grains that leave through one side come back through the other.
TEST(SphereKernel3d, PeriodicSidesCollideLikeTheMiddle) {
  World3d across(parse_scene(periodic_scene(0), "<across>")),
      middle(parse_scene(periodic_scene(10), "<mid>"));
  Vec3 p0 = Vec3::Zero();
  for (const Body3& b : across.bodies()) p0 += b.m * b.v;
  across.advance_to(0.05), middle.advance_to(0.05);
  ASSERT_TRUE(across.on_sphere_kernel());
  const Body3 &a = across.bodies()[0], &b = middle.bodies()[0];
  EXPECT_LT(a.v.x(), -10);  // it bounced back
  EXPECT_NEAR(a.v.x(), b.v.x(), 1e-9);
  EXPECT_NEAR(a.v.y(), b.v.y(), 1e-9);
  EXPECT_NEAR((a.w - b.w).norm(), 0, 1e-9);
  Vec3 p1 = Vec3::Zero();
  for (const Body3& c : across.bodies()) p1 += c.m * c.v;
  EXPECT_LT((p1 - p0).norm(), 1e-9 * p0.norm() + 1e-9);
  across.advance_to(1.0);  // at 40-50 cm/s the pair crosses the x sides twice more
  for (const Body3& c : across.bodies()) {
    EXPECT_GT(c.x.x(), -0.2);
    EXPECT_LT(c.x.x(), 20.2);
    EXPECT_GT(c.x.y(), -0.2);
    EXPECT_LT(c.x.y(), 12.2);
  }
}

TEST(SphereKernel3d, PeriodicBoxesNeedTheSphereKernel) {
  std::string s = periodic_scene(10);
  s.replace(s.find("\"verlet\""), 8, "\"predictor-corrector\"");
  World3d w(parse_scene(s, "<pc>"));
  EXPECT_THROW(w.advance_to(1e-4), InputError);
  EXPECT_THROW(parse_scene("[scene]\nname = \"p\"\nduration = 1\nperiodic_y = [0, 1]\n", "<2d>"), InputError);
}

}  // namespace grainlab::dem

namespace grainlab::dem {

// A bed steps in one sweep whenever no list rebuild is due (drift sphere t, then the row of sphere t - L);
// otherwise it drifts all, then runs the rows. Here one bed always sweeps when it can and the other, also
// distributed (on a single rank: the ghost machinery with nobody to talk to), never does. The two must
// give the same bits: the sweep's reordering is only valid if every row sees its partners
// drifted and no partner drifts after a row has added to it. A hot, periodic gas makes lists go stale
// often, so both paths and the switching between them are exercised.
TEST(SphereKernel3d, OneSweepEqualsTwoPassesBitForBit) {
  std::string t = std::string(R"toml(
[scene]
name = "hot periodic gas"
dimension = 3
duration = 1.0
periodic_x = [0.0, 8.0]
periodic_y = [0.0, 6.0]
effects = ["gravity", "normal_contact", "friction", "rotation"]
)toml") + kVerletGrain +
                  "[[walls]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 1]\n";
  Rng rng(5, 0);
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 2; ++k)
        t += fmt::format(
            "[[bodies]]\nshape = \"sphere\"\nradius = {}\ndensity = 2.65\nposition = [{}, {}, {}]\n"
            "velocity = [{}, {}, {}]\nspin = [{}, {}, {}]\n",
            rng.uniform(0.4, 0.5), 0.5 + i, 0.5 + j, 0.5 + k, rng.uniform(-30, 90), rng.uniform(-60, 60),
            rng.uniform(-20, 20), rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
  const Scene scene = parse_scene(t, "<gas>");
  World3d sweep(scene), passes(scene, Decomposition{true, 0, 1});
  passes.allow_sweep(false);
  for (int k = 1; k <= 8; ++k) {
    sweep.advance_to(k * 250 * 2e-5);
    passes.advance_to(k * 250 * 2e-5);
  }
  ASSERT_TRUE(sweep.on_sphere_kernel());
  ASSERT_TRUE(passes.distributed());
  EXPECT_GT(sweep.count_contacts(), 10u);
  EXPECT_EQ(sweep.count_contacts(), passes.count_contacts());
  for (std::size_t i = 0; i < sweep.bodies().size(); ++i) {
    const Body3 &a = sweep.bodies()[i], &b = passes.bodies()[i];
    EXPECT_EQ(a.x, b.x) << "body " << a.id;
    EXPECT_EQ(a.v, b.v) << "body " << a.id;
    EXPECT_EQ(a.w, b.w) << "body " << a.id;
  }
  EXPECT_EQ(sweep.energies().total(), passes.energies().total());
}

}  // namespace grainlab::dem
