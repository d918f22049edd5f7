// Poured beds of irregular convex grains (3-D assemblies with shape = "polyhedron"): every grain is a
// valid convex polyhedron with the volume of the sphere of its drawn radius, the shapes differ, the pour
// comes to rest on the floor inside the box, the same seed gives the same bed, and the scene reader
// refuses what it cannot build.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "input_error.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {

std::string poured(const std::string& extra) {
  return fmt::format(R"toml(
[scene]
name = "irregular grains"
dimension = 3
duration = 0.01
seed = 3
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.sand]
k_n = 1e6
k_s = 1e6
mu = 0.5
restitution = 0.2
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [6.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, 6.0, 0.0]
normal = [0.0, -1.0, 0.0]
[[assemblies]]
type = "poured"
count = 24
width = 6.0
depth = 6.0
origin = [0.0, 0.0, 0.0]
density = 2.65
settle_time = 0.6
{}
[assemblies.radius_distribution]
kind = "uniform"
min = 0.4
max = 0.5
)toml",
                     extra);
}

double lowest_point(const Body3Spec& b) {
  double z = 1e300;
  for (const Vec3& v : b.hull.vertices) z = std::min(z, (b.position + b.orientation * v).z());
  return z;
}

}  // namespace

TEST(IrregularGrains, PouredPolyhedraAreValidRestAndRepeat) {
  const Scene scene =
      parse_scene(poured("shape = \"polyhedron\"\nirregularity = 0.25\nelongation = 0.3"), "<poly>");
  const std::vector<Body3Spec> bed = expanded_bodies3d(scene), again = expanded_bodies3d(scene);
  ASSERT_EQ(bed.size(), 24u);
  double smallest_ratio = 1e300, largest_ratio = 0;
  for (std::size_t i = 0; i < bed.size(); ++i) {
    const Body3Spec& b = bed[i];
    ASSERT_EQ(b.shape, Body3Spec::Shape::Polyhedron);
    Polyhedron rebuilt;
    EXPECT_EQ(make_polyhedron(b.hull.vertices, b.hull.faces, rebuilt), "") << i;  // closed, convex, outward
    const SolidMass m = polyhedron_mass(b.hull);
    const double r_eq = std::cbrt(3 * m.volume / (4 * M_PI));
    EXPECT_GE(r_eq, 0.4 - 1e-9) << i;
    EXPECT_LE(r_eq, 0.5 + 1e-9) << i;
    EXPECT_NEAR(m.centroid.norm(), 0, 1e-9 * r_eq) << i;  // body frame at the centroid
    EXPECT_NEAR(b.mass, 2.65 * m.volume, 1e-9 * b.mass) << i;
    const double ratio = b.radius / r_eq;  // bounding over equivalent radius: 1 for a sphere
    smallest_ratio = std::min(smallest_ratio, ratio), largest_ratio = std::max(largest_ratio, ratio);
    // At rest inside the box: above the floor (to the contact's overlap) and inside the side planes.
    EXPECT_GT(lowest_point(b), -0.01) << i;
    EXPECT_LT(b.position.z(), 3.0) << i;
    EXPECT_GT(b.position.x(), 0) << i;
    EXPECT_LT(b.position.x(), 6) << i;
    EXPECT_LT(b.velocity.norm(), 1e-12) << i;       // handed over at rest (the assembly's velocity)
    EXPECT_EQ(b.position, again[i].position) << i;  // the same seed, the same bed
    EXPECT_EQ(b.hull.vertices, again[i].hull.vertices) << i;
  }
  EXPECT_GT(smallest_ratio, 1.05);                  // no grain is a sphere ...
  EXPECT_GT(largest_ratio - smallest_ratio, 0.05);  // ... and they are not all alike
  // The settled bed: the scene runs on from it with the grains nearly still.
  World3d w(scene);
  w.advance_to(0.01);
  double fastest = 0;
  for (const Body3& b : w.bodies()) fastest = std::max(fastest, b.v.norm());
  EXPECT_LT(fastest, 5.0);  // cm/s, against ~340 cm/s of a grain that fell the pour's 6 cm
}

// The general path shares its narrow phase and integration between threads from 256 bodies on; the
// forces are summed in one thread in the serial order, so any number of threads gives the same bits.
TEST(IrregularGrains, ThreadsChangeNoBit) {
  std::string text = poured("shape = \"polyhedron\"\nirregularity = 0.25\nelongation = 0.3");
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"count = 24", "count = 260"},
           {"settle_time = 0.6", "settle_time = 0.2"},
           {"width = 6.0", "width = 9.0"},
           {"depth = 6.0", "depth = 9.0"},
           {"point = [6.0, 0.0, 0.0]", "point = [9.0, 0.0, 0.0]"},
           {"point = [0.0, 6.0, 0.0]", "point = [0.0, 9.0, 0.0]"}})
    text.replace(text.find(from), from.size(), to);
  const Scene scene = parse_scene(text, "<threads>");
  ASSERT_GE(expanded_bodies3d(scene).size(), 256u);
  std::vector<std::vector<Body3>> runs;
  std::size_t contacts = 0;
  for (int threads : {1, 2, 3}) {
    World3d w(scene);
    w.use_threads(threads);
    w.advance_to(0.01);
    runs.push_back(w.bodies());
    if (threads == 1) contacts = w.count_contacts();
  }
  EXPECT_GT(contacts, 100u)
      << contacts;  // grains on the floor and on each other: the contacts were exercised
  for (std::size_t k = 1; k < runs.size(); ++k)
    for (std::size_t i = 0; i < runs[0].size(); ++i) {
      EXPECT_EQ(runs[k][i].x, runs[0][i].x) << k << " " << i;
      EXPECT_EQ(runs[k][i].v, runs[0][i].v) << k << " " << i;
      EXPECT_EQ(runs[k][i].q.coeffs(), runs[0][i].q.coeffs()) << k << " " << i;
      EXPECT_EQ(runs[k][i].w, runs[0][i].w) << k << " " << i;
    }
}

TEST(IrregularGrains, SceneReaderRefusesWhatItCannotBuild) {
  EXPECT_THROW(parse_scene(poured("shape = \"cube\""), "<bad>"), InputError);
  EXPECT_THROW(parse_scene(poured("shape = \"polyhedron\"\nirregularity = 0.5"), "<bad>"), InputError);
  EXPECT_THROW(parse_scene(poured("elongation = 0.2"), "<bad>"), InputError);  // spheres take no shape keys
  std::string lattice = poured("shape = \"polyhedron\"");
  lattice.replace(lattice.find("type = \"poured\""), 15,
                  "type = \"lattice\"\nnx = 2\nny = 2\nnz = 2\nspacing = 1.2");
  EXPECT_THROW(parse_scene(lattice, "<bad>"), InputError);
}

}  // namespace grainlab::dem
