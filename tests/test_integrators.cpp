#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "scene.hpp"
#include "world.hpp"

using namespace grainlab;

namespace {
std::string free_flight(const std::string& integrator) {
  return fmt::format(R"toml(
[scene]
duration = 1.0
effects = ["gravity"]
[accuracy]
integrator = "{}"
dt = 1e-3
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 0.0]
velocity = [100.0, 300.0]
)toml",
                     integrator);
}
}  // namespace

TEST(Integrators, FreeFlightFollowsTheParabola) {
  for (const char* integ : {"predictor-corrector", "verlet"}) {
    dem::World w(parse_scene(free_flight(integ), "<flight>"));
    w.advance_to(1.0);
    EXPECT_NEAR(w.time(), 1.0, 1e-9) << integ;
    EXPECT_NEAR(w.particles().x[0], 100.0, 1e-9) << integ;
    EXPECT_NEAR(w.particles().y[0], 300.0 - 0.5 * 981.0, 1e-8) << integ;  // both are exact for constant force
  }
}

TEST(Integrators, PredictorCorrectorRejectsAndHalvesAtContact) {
  const std::string toml = R"toml(
[scene]
duration = 1.0
effects = ["gravity", "normal_contact"]
[accuracy]
tolerance = 0.001
dt = 1e-3
dt_max = 1e-2
[materials.grain]
k_n = 1e6
restitution = 0.8
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 10.0]
)toml";
  dem::World w(parse_scene(toml, "<bounce>"));
  w.advance_to(0.25);
  const auto& d = w.diagnostics();
  EXPECT_GT(d.rejected_steps, 0u);
  EXPECT_LT(d.dt_min_used, d.dt_max_used / 100);  // small steps in contact, large in flight
  // It bounced: moving up after the first impact (fall time 0.135 s, contact ~4 ms).
  EXPECT_GT(w.particles().vy[0], 0.0);
}

TEST(Integrators, SquareDroppedOnFloorComesToRestOnAFace) {
  const std::string toml = R"toml(
[scene]
duration = 3.0
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.rock]
k_n = 1e6
restitution = 0.3
k_s = 1e6
mu = 0.5
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [0.0, 4.0]
angle = 0.5
)toml";
  dem::World w(parse_scene(toml, "<square>"));
  w.advance_to(3.0);
  const auto& p = w.particles();
  EXPECT_LT(w.energies().kinetic(), 1e-3);
  EXPECT_NEAR(p.y[0], 1.0, 0.01);     // resting on a face: centre one half-side up
  EXPECT_EQ(w.count_contacts(), 2u);  // its two lower vertices
  const double a = std::fmod(std::abs(p.th[0]), M_PI / 2);
  EXPECT_LT(std::min(a, M_PI / 2 - a), 0.01);
}

TEST(Integrators, PolygonsCollideAndConserveMomentum) {
  const std::string toml = R"toml(
[scene]
duration = 0.2
effects = ["normal_contact", "friction", "rotation"]
[accuracy]
tolerance = 1e-4
[materials.rock]
k_n = 1e6
restitution = 0.5
k_s = 1e6
mu = 0.3
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [-2.0, 0.3]
angle = 0.3
velocity = [50.0, 0.0]
[[bodies]]
shape = "polygon"
vertices = [[0.0, -1.2], [1.1, -0.4], [0.8, 1.0], [-0.7, 1.1], [-1.2, -0.2]]
density = 2.0
position = [2.0, 0.0]
velocity = [-50.0, 0.0]
)toml";
  dem::World w(parse_scene(toml, "<polygons>"));
  w.advance_to(0.2);
  const auto& p = w.particles();
  const double px = p.m[0] * p.vx[0] + p.m[1] * p.vx[1], py = p.m[0] * p.vy[0] + p.m[1] * p.vy[1];
  const double scale = p.m[0] * 50 + p.m[1] * 50;
  EXPECT_LT(std::hypot(px - (p.m[0] - p.m[1]) * 50, py) / scale, 1e-9);
  EXPECT_LT(p.vx[0], 0.0);  // they bounced apart
  EXPECT_GT(p.vx[1], 0.0);
}

TEST(Integrators, PeriodicBoundaryCarriesContacts) {
  const std::string toml = R"toml(
[scene]
duration = 0.1
periodic_x = [0.0, 20.0]
effects = ["normal_contact"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.grain]
k_n = 1e6
[[bodies]]
radius = 1.0
density = 2.0
position = [1.5, 0.0]
velocity = [-100.0, 0.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [18.5, 0.0]
)toml";
  dem::World w(parse_scene(toml, "<periodic>"));
  w.advance_to(0.1);
  // Elastic, equal masses: the moving disc stops and the other leaves at its speed, across the seam.
  EXPECT_NEAR(w.particles().vx[w.index_of(0)], 0.0, 0.5);
  EXPECT_NEAR(w.particles().vx[w.index_of(1)], -100.0, 0.5);
}

TEST(Integrators, DiscBouncesOffAPolygonConservingEnergyWhenElastic) {
  // A disc falls onto a heavy square resting on... nothing: no gravity, the square floats. Elastic,
  // frictionless: kinetic energy after the bounce equals that before (the polygon-disc contact is a
  // conservative spring), and momentum is exchanged.
  const std::string toml = R"toml(
[scene]
duration = 0.05
effects = ["normal_contact", "rotation"]
[accuracy]
tolerance = 1e-5
[materials.grain]
k_n = 1e6
[[bodies]]
shape = "polygon"
vertices = [[-2.0, -2.0], [2.0, -2.0], [2.0, 2.0], [-2.0, 2.0]]
density = 2.0
position = [0.0, 0.0]
angle = 0.2
[[bodies]]
radius = 0.5
density = 2.0
position = [0.3, 3.6]
velocity = [0.0, -100.0]
)toml";
  dem::World w(parse_scene(toml, "<disc on polygon>"));
  const double e0 = w.energies().total();
  w.advance_to(0.05);
  const auto& p = w.particles();
  const long disc = w.index_of(1);
  EXPECT_GT(p.vy[disc], 0.0);  // bounced
  EXPECT_NEAR(w.energies().total(), e0, 1e-3 * e0);
  EXPECT_NEAR(w.energies().elastic, 0.0, 1e-9 * e0);  // apart again at the end
}

TEST(Integrators, FrictionlessPolygonContactsAreCounted) {
  // Contact counting must not depend on shear history, which a frictionless scene does not keep.
  const std::string toml = R"toml(
[scene]
duration = 1.0
effects = ["gravity", "normal_contact"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.rock]
k_n = 1e6
restitution = 0.3
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [0.0, 0.999]
)toml";
  dem::World w(parse_scene(toml, "<frictionless square>"));
  w.advance_to(0.5);
  EXPECT_EQ(w.history_entries(), 0u);
  EXPECT_EQ(w.count_contacts(), 2u);
}

TEST(Integrators, PolygonContactsCountTheirShearSpringEnergy) {
  // A square tumbles onto a line and rocks to rest. Energy only leaves (the dashpots, and springs whose
  // anchor slides), so kinetic + gravity + normal + shear springs must never rise between two looks (to
  // Verlet's round-off). Its vertex contacts hold energy in their shear springs and give it back as they
  // part: a total that left them out would rise then.
  const std::string toml = R"toml(
[scene]
duration = 0.6
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-6
[materials.rock]
k_n = 1e6
k_s = 1e6
restitution = 0.5
mu = 2.0
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [0.0, 1.6]
angle = 0.35
velocity = [40.0, -30.0]
spin = 12.0
)toml";
  dem::World w(parse_scene(toml, "<tumbling square>"));
  double before = w.energies().total();
  const double e0 = before;
  double rise = 0, most_elastic = 0;
  for (int k = 1; k <= 1200; ++k) {
    w.advance_to(k * 5e-4);
    const dem::Energies e = w.energies();
    rise = std::max(rise, e.total() - before);
    most_elastic = std::max(most_elastic, e.elastic);
    before = e.total();
  }
  EXPECT_GT(most_elastic, 1e-2 * e0);  // the contacts did hold energy
  EXPECT_LT(rise, 1e-4 * e0);
}
