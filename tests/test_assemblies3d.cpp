// Generated 3-D beds: a lattice lands where asked with sphere masses; a pour settles into its box at a
// random packing fraction, the same for the same seed; bad keys are refused by name.
#include <gtest/gtest.h>

#include <cmath>

#include "input_error.hpp"
#include "sand_spheres3d.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {

// A box of five planes (floor and four sides) 12 cm square, k_n high enough that overlaps stay below
// 1e-4 of a radius under a bed's weight.
const std::string kBox = std::string(R"toml(
[scene]
dimension = 3
duration = 0.001
seed = 11
)toml") + kSandSpheres3dOnAFloor +
                         R"toml(
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [12.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, 12.0, 0.0]
normal = [0.0, -1.0, 0.0]
)toml";

Scene box_with(const std::string& assemblies) {
  return parse_scene(std::string(kBox) + assemblies, "box.toml");
}

// 300 spheres of radii 0.8-1.0 cm poured into the box: about three layers.
constexpr const char* kPour300 = R"toml(
[[assemblies]]
type = "poured"
count = 300
width = 12.0
depth = 12.0
origin = [0.0, 0.0, 0.0]
density = 2.65
settle_time = 0.25
[assemblies.radius_distribution]
kind = "uniform"
min = 0.8
max = 1.0
)toml";

// A pour is the densest work the sphere kernel does: grains landing on grains, loaded springs that slide,
// spins, a floor and four sides. The serial sweep computes its rows' pairs in blocks, four at a time
// (sphere_pair_batch.hpp); a bed distributed on one rank with the sweep off computes them one by one in
// each row. They must give the same bits, body for body, through the pour.
TEST(Assemblies3d, APourInBlocksOfFourPairsIsThePourPairByPair) {
  const Scene settle = pour_settling_scene(box_with(kPour300));
  World3d blocks(settle), pairs(settle, Decomposition{true, 0, 1});
  pairs.allow_sweep(false);
  std::size_t most = 0;
  for (int k = 1; k <= 10; ++k) {
    blocks.advance_to(0.25 * k / 10);
    pairs.advance_to(0.25 * k / 10);
    ASSERT_EQ(blocks.count_contacts(), pairs.count_contacts()) << "at t = " << blocks.time();
    most = std::max(most, blocks.count_contacts());
  }
  ASSERT_TRUE(blocks.on_sphere_kernel());
  // A bed, and so the blocks (taken from a quarter of a contact a grain, 75 here) were used: more contacts
  // than grains (372 at most in this pour).
  EXPECT_GT(most, 300u);
  for (std::size_t i = 0; i < blocks.bodies().size(); ++i) {
    const Body3 &a = blocks.bodies()[i], &b = pairs.bodies()[i];
    ASSERT_EQ(a.x, b.x) << "body " << a.id;
    ASSERT_EQ(a.v, b.v) << "body " << a.id;
    ASSERT_EQ(a.w, b.w) << "body " << a.id;
  }
  EXPECT_EQ(blocks.energies().total(), pairs.energies().total());
}

TEST(Assemblies3d, LatticeSpheresSitWhereAsked) {
  const Scene s = box_with(R"toml(
[[bodies]]
radius = 0.5
density = 1.0
position = [6.0, 6.0, 20.0]
[[assemblies]]
type = "lattice"
nx = 4
ny = 3
nz = 2
spacing = 2.5
origin = [1.5, 1.5, 1.2]
density = 2.65
radius = 1.0
velocity = [0.0, 0.0, -10.0]
)toml");
  const std::vector<Body3Spec> b = expanded_bodies3d(s);
  ASSERT_EQ(b.size(), 1u + 4 * 3 * 2);
  EXPECT_EQ(b[1].id, 1);  // numbered after the scene's own bodies
  EXPECT_DOUBLE_EQ(b[1].mass, 2.65 * 4.0 / 3.0 * M_PI);
  EXPECT_DOUBLE_EQ(b[1].inertia(0, 0), 0.4 * b[1].mass);
  // x fastest, then y, then z.
  EXPECT_DOUBLE_EQ(b[2].position.x(), 4.0);
  EXPECT_DOUBLE_EQ(b[1 + 4].position.y(), 4.0);
  EXPECT_DOUBLE_EQ(b[1 + 12].position.z(), 3.7);
  EXPECT_DOUBLE_EQ(b[5].velocity.z(), -10.0);
  EXPECT_EQ(World3d(s).bodies().size(), b.size());
}

// Solid fraction inside the box [lo, hi]: the share of a 24^3 grid of points that lie in a sphere.
double solid_fraction(const std::vector<Body3Spec>& b, const Vec3& lo, const Vec3& hi) {
  const int n = 24;
  int inside = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 p = lo + (hi - lo).cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5) / n);
        for (const Body3Spec& s : b)
          if ((p - s.position).squaredNorm() < s.radius * s.radius) {
            ++inside;
            break;
          }
      }
  return double(inside) / (n * n * n);
}

TEST(Assemblies3d, PouredBedSettlesAtRandomPacking) {
  const std::vector<Body3Spec> b = expanded_bodies3d(box_with(kPour300));
  ASSERT_EQ(b.size(), 300u);
  double top = 0;
  for (const Body3Spec& s : b) {
    // Inside the box (planes overlap grains by well under 1e-3 of a radius).
    EXPECT_GT(s.position.x() - s.radius, -1e-3);
    EXPECT_LT(s.position.x() + s.radius, 12 + 1e-3);
    EXPECT_GT(s.position.y() - s.radius, -1e-3);
    EXPECT_GT(s.position.z() - s.radius, -1e-3);
    top = std::max(top, s.position.z() + s.radius);
  }
  // Out of the loose grid (pitch 2.2: 5 x 5 columns, 12 layers up to z = 27, solid fraction 0.18) into a
  // bed. Away from the walls (one diameter in) and the rough top, frictional spheres settle between
  // random loose packing, which is no lower than 0.536 even for infinite friction (Song, Wang & Makse
  // 2008), and random close packing, 0.64 (a little more for this 20 % spread of sizes: 0.65).
  const double phi = solid_fraction(b, Vec3(2, 2, 2), Vec3(10, 10, 0.7 * top));
  EXPECT_GT(phi, 0.536);
  EXPECT_LT(phi, 0.65);
  // Settled, not still falling: the whole bed (927 cm^3 of grains) below the height it would fill at
  // packing 0.45, plus a rough top of two diameters.
  double solid = 0;
  for (const Body3Spec& s : b) solid += 4.0 / 3.0 * M_PI * std::pow(s.radius, 3);
  EXPECT_LT(top, solid / (0.45 * 12 * 12) + 4.0);
  RecordProperty("packing", std::to_string(phi));
  RecordProperty("top", std::to_string(top));
  for (std::size_t i = 0; i < b.size(); ++i)
    for (std::size_t j = i + 1; j < b.size(); ++j)
      EXPECT_GT((b[i].position - b[j].position).norm(), (b[i].radius + b[j].radius) * (1 - 1e-3));
  // The same seed gives the same bed; another seed another.
  const std::vector<Body3Spec> again = expanded_bodies3d(box_with(kPour300));
  EXPECT_EQ(again[123].position, b[123].position);
  Scene other = box_with(kPour300);
  other.seed = 12;
  EXPECT_NE(expanded_bodies3d(other)[123].position, b[123].position);
}

// A pour as the run it takes (what a caller runs, and checkpoints, itself): advanced for the settle time,
// in one piece or in slices, it leaves the grains where expanded_bodies3d puts them, bit for bit.
TEST(Assemblies3d, APourRunByTheCallerMakesTheSameBed) {
  const Scene scene = box_with(R"toml(
[[assemblies]]
type = "poured"
count = 60
width = 12.0
depth = 12.0
origin = [0.0, 0.0, 0.0]
density = 2.65
settle_time = 0.05
radius = 0.9
)toml");
  const std::vector<Body3Spec> made = expanded_bodies3d(scene);
  for (int slices : {1, 7}) {
    const Scene settle = pour_settling_scene(scene);
    World3d w(settle);
    for (int k = 1; k <= slices; ++k) w.advance_to(scene.assemblies[0].settle_time * k / slices);
    ASSERT_EQ(w.bodies().size(), made.size());
    for (std::size_t i = 0; i < made.size(); ++i) {
      EXPECT_EQ(w.bodies()[i].x, made[i].position) << slices << " slices, grain " << i;
      EXPECT_EQ(w.bodies()[i].q.coeffs(), made[i].orientation.coeffs()) << slices << " slices, grain " << i;
    }
  }
  EXPECT_THROW(pour_settling_scene(box_with("")), std::invalid_argument);
}

TEST(Assemblies3d, BadKeysAreRefusedByName) {
  auto refused_for = [](const std::string& assembly) {
    try {
      box_with(assembly);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string lattice = R"toml(
[[assemblies]]
type = "lattice"
nx = 2
ny = 2
origin = [0.0, 0.0, 1.0]
density = 2.65
radius = 1.0
spacing = 2.0
)toml";
  EXPECT_NE(refused_for(lattice).find("nz"), std::string::npos);  // layers are required in 3-D
  EXPECT_NE(refused_for(lattice + "nz = 2\nspacing_typo = 1\n").find("spacing_typo"), std::string::npos);
  std::string close = lattice + "nz = 2\n";
  close.replace(close.find("spacing = 2.0"), 13, "spacing = 1.9");
  EXPECT_NE(refused_for(close).find("spacing"), std::string::npos);
  std::string flat = lattice + "nz = 2\n";
  flat.replace(flat.find("[0.0, 0.0, 1.0]"), 15, "[0.0, 0.0]");
  EXPECT_NE(refused_for(flat).find("origin"), std::string::npos);
  EXPECT_NE(refused_for(R"toml(
[[assemblies]]
type = "poured"
count = 10
width = 12.0
origin = [0.0, 0.0, 0.0]
density = 2.65
radius = 1.0
)toml")
                .find("depth"),
            std::string::npos);
  EXPECT_NE(refused_for(R"toml(
[[assemblies]]
type = "poured"
count = 10
width = 12.0
depth = 12.0
origin = [0.0, 0.0, 0.0]
sphere_density = 2.65
radius = 1.0
)toml")
                .find("sphere_density"),
            std::string::npos);
}

}  // namespace

}  // namespace grainlab::dem
