// The wind_drag and buoyancy effects (issue #18): scene keys and refusals, the drag laws and the wind
// column against analytic limits, a grain's terminal velocity, and the engine's wind across checkpoints.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "cli_helpers.hpp"
#include "fluid.hpp"
#include "scene.hpp"
#include "world.hpp"
#include "world3d.hpp"

using namespace grainlab;
using namespace cli_test;

namespace {

// A small periodic bed with a wind (effects as given).
std::string windy_scene(
    const std::string& effects = R"("gravity", "normal_contact", "friction", "wind_drag")",
    const std::string& wind = "u_star = 40.0\n") {
  return fmt::format(R"toml([scene]
duration = 0.002
periodic_x = [0.0, 1.5]
effects = [{}]
[accuracy]
integrator = "verlet"
dt = 1e-6
[materials.sand]
k_n = 2.0e5
restitution = 0.9
k_s = 1.0e5
mu = 0.5
[fluid]
grain_density = 2.65
[wind]
{}[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[assemblies]]
type = "lattice"
nx = 50
ny = 4
spacing = 0.03
origin = [0.015, 0.015]
sphere_density = 2.65
radius = 0.0125
[[bodies]]
id = 1000
radius = 0.0125
density = 0.0442
position = [0.7, 0.4]
velocity = [50.0, 30.0]
)toml",
                     effects, wind);
}

std::string thrown(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(WindScene, KeysAreReadAndCheckedByName) {
  const Scene s = parse_scene(windy_scene(), "<windy>");
  EXPECT_TRUE(s.effects.has(Effect::wind_drag));
  EXPECT_EQ(s.wind.u_star, 40.0);
  EXPECT_EQ(s.fluid.grain_density, 2.65);
  // A [wind] table without the effect that reads it, or the effect without its table.
  EXPECT_NE(
      thrown([] { parse_scene(windy_scene(R"("gravity", "normal_contact")"), "<x>"); }).find("wind_drag"),
      std::string::npos);
  std::string no_table = windy_scene();
  no_table.replace(no_table.find("[wind]\nu_star = 40.0\n"), 21, "");
  EXPECT_NE(thrown([&] { parse_scene(no_table, "<x>"); }).find("wind"), std::string::npos);
  EXPECT_NE(
      thrown([] { parse_scene(windy_scene(R"("normal_contact", "buoyancy")"), "<x>"); }).find("gravity"),
      std::string::npos);
  for (const std::string bad : {"u_star = -1.0\n", "u_star = nan\n", "u_star = 40.0\nmodel = \"k-epsilon\"\n",
                                "u_star = 40.0\nupdate_interval = 0.0\n", "u_star = 40.0\ndrag_law = \"x\"\n",
                                "u_star = 40.0\nkappa = 4.0\n", "u_star = 40.0\nspeed = 3.0\n"}) {
    const std::string what =
        thrown([&] { parse_scene(windy_scene(R"("gravity", "wind_drag")", bad), "<x>"); });
    EXPECT_NE(what.find("wind"), std::string::npos) << bad << ": " << what;
  }
  EXPECT_NE(thrown([] {
              parse_scene(windy_scene().replace(windy_scene().find("grain_density = 2.65"), 20,
                                                "grain_density = 0.001"),
                          "<x>");
            }).find("density"),
            std::string::npos);
}

TEST(WindScene, ShippedSaltationBedLoads) {
  const Scene s = load_scene(std::string(GRAINLAB_SOURCE_DIR) + "/scenes/saltation_bed.toml");
  EXPECT_TRUE(s.effects.has(Effect::wind_drag));
  EXPECT_TRUE(s.effects.has(Effect::buoyancy));
}

TEST(WindScene, RigidEnginesRefuseWindDragByNameAndWriteNothing) {
  Dir d;
  { std::ofstream(d.path / "w.toml") << windy_scene(); }
  for (const std::string engine : {"box2d", "ode", "bullet"}) {
    const fs::path out = d.path / (engine + ".h5");
    const Outcome o = cli_test::grainlab(
        "run " + (d.path / "w.toml").string() + " --engine " + engine + " --quiet --out " + out.string(),
        d.path);
    EXPECT_EQ(o.status, 2) << engine << ": " << o.err;
    EXPECT_NE(o.err.find("wind_drag"), std::string::npos) << engine << ": " << o.err;
    EXPECT_FALSE(fs::exists(out)) << engine;
  }
  const Outcome ok = cli_test::grainlab(
      "run " + (d.path / "w.toml").string() + " --quiet --out " + (d.path / "native.h5").string(), d.path);
  EXPECT_EQ(ok.status, 0) << ok.err;
}

TEST(WindScene, HostileWindValuesNeverCrash) {
  // Seeded mutations of the [wind] and [fluid] values: each is either run or refused with status 2.
  Dir d;
  std::mt19937_64 rng(18);
  const std::vector<std::string> values = {"0.0",   "-3.0",  "1e300", "nan",  "inf",
                                           "\"x\"", "[1.0]", "true",  "1e-30"};
  const std::vector<std::string> keys = {"u_star",          "roughness", "bin_height", "top",
                                         "update_interval", "thickness", "bed_level",  "kappa"};
  for (int k = 0; k < 24; ++k) {
    const std::string key = keys[rng() % keys.size()], value = values[rng() % values.size()];
    const std::string wind =
        key == "u_star" ? "u_star = " + value + "\n" : "u_star = 40.0\n" + key + " = " + value + "\n";
    { std::ofstream(d.path / "w.toml") << windy_scene(R"("gravity", "normal_contact", "wind_drag")", wind); }
    const fs::path out = d.path / "w.h5";
    fs::remove(out);
    const Outcome o =
        cli_test::grainlab("run " + (d.path / "w.toml").string() + " --quiet --out " + out.string(), d.path);
    EXPECT_TRUE(o.status == 0 || o.status == 2)
        << key << " = " << value << ": status " << o.status << " " << o.err;
    if (o.status == 2) {
      EXPECT_FALSE(fs::exists(out)) << key << " = " << value;
      EXPECT_NE(o.err.find("grainlab: error:"), std::string::npos) << o.err;
    }
  }
}

TEST(Fluid, DragLawsHaveTheirLimits) {
  // Stokes: c_d Re -> 24 for both laws (thesis: 24 + 6 Re/(1+sqrt Re) + ...; Dalla Valle: 4.8^2 = 23.04).
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::Thesis, 1e-6) * 1e-6, 24, 1e-3);
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::DallaValle, 1e-8) * 1e-8, 23.04, 1e-2);
  // Newton: the thesis's 0.4, Dalla Valle's 0.63^2.
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::Huo2021, 1e-8) * 1e-8, 24, 1e-2);
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::Thesis, 1e12), 0.4, 1e-5);
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::Huo2021, 1e14), 0.5, 1e-5);
  EXPECT_NEAR(fluid::drag_coefficient(WindSpec::DragLaw::DallaValle, 1e14), 0.3969, 1e-5);
}

TEST(Fluid, CleanColumnIsTheLogLaw) {
  // No grains: the steady column is u = (u*/kappa) ln(z/z0) (eq. 4.28 with u*_eff = u*).
  fluid::WindProfileInput in{WindSpec::Model::MixingLength, 0.4, 0.025 / 30, 0.146, 40};
  const double dz = 0.0125;
  std::vector<double> z, zero;
  for (int k = 0; k < 2000; ++k) z.push_back((k + 0.5) * dz - 0.05), zero.push_back(0);
  std::vector<double> u(z.size(), 1.0), eddy;  // a poor start: the fixed point must find the log law
  for (int pass = 0; pass < 60; ++pass)
    u = fluid::advance_wind_column(in, dz, z, u, zero, zero, std::numeric_limits<double>::infinity(), eddy);
  for (double at : {0.1, 1.0, 10.0, 20.0}) {
    const auto k = static_cast<std::size_t>((at + 0.05) / dz);
    EXPECT_NEAR(u[k], 40 / 0.4 * std::log(z[k] / in.roughness), 0.01 * u[k]) << "z = " << z[k];
  }
  // Van Driest over a smooth wall: u+ = z+ in the viscous sublayer.
  fluid::WindProfileInput vd{WindSpec::Model::VanDriest, 0.4, 1e-9, 0.146, 40};
  std::vector<double> zs, zeros;
  for (int k = 0; k < 4000; ++k) zs.push_back((k - 0.5) * 1e-4), zeros.push_back(0);  // a held cell at z < 0
  std::vector<double> v(zs.size(), 1.0), eddy_vd;
  for (int pass = 0; pass < 60; ++pass)
    v = fluid::advance_wind_column(vd, 1e-4, zs, v, zeros, zeros, std::numeric_limits<double>::infinity(),
                                   eddy_vd);
  const double z_plus = zs[5] * 40 / 0.146;  // about 1.5
  EXPECT_NEAR(v[5] / 40, z_plus, 0.05 * z_plus);
}

TEST(Fluid, ColumnConservesMomentum) {
  // Whatever the grains' drag, the stress in at the top is what they take plus what reaches the bed.
  fluid::WindProfileInput in{WindSpec::Model::MixingLength, 0.4, 0.025 / 30, 0.146, 40};
  const double dz = 0.0125;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<double> z, a, b, s;
  for (int k = 0; k < 800; ++k) {
    z.push_back((k + 0.5) * dz - 0.02);
    const bool grains = k > 2 && k < 60 && U(rng) < 0.5;
    a.push_back(grains ? 2000 * U(rng) : 0.0), b.push_back(grains ? a.back() * 300 * U(rng) : 0.0);
    s.push_back(1600);
  }
  std::vector<double> u = fluid::wind_profile(in, z, s);
  for (double dt : {1e-3, std::numeric_limits<double>::infinity()}) {
    std::vector<double> eddy;
    const std::vector<double> next = fluid::advance_wind_column(in, dz, z, u, a, b, dt, eddy);
    double taken = 0, stored = 0;
    std::size_t first = 0;
    while (z[first] <= in.roughness) ++first;
    for (std::size_t k = first; k < z.size(); ++k) {
      taken += (a[k] * next[k] - b[k]) * dz;
      if (std::isfinite(dt)) stored += (next[k] - u[k]) / dt * dz;
    }
    // The bed's share with the conductance the step used (that of the incoming profile).
    const double bed = fluid::face_conductance(in, dz, z, u, first - 1) * next[first] / dz;
    EXPECT_NEAR(taken + stored + bed, 1600, 1e-6 * 1600) << "dt = " << dt;
  }
}

TEST(WindEngine, GrainFallsAtItsTerminalVelocity) {
  // One grain dropped in still air (a wind of u* = 0): gravity, buoyancy and the thesis's drag balance
  // at m g (1 - rho_f/rho_s) = c(v) m v, v from the drag law by bisection.
  const std::string scene = R"toml([scene]
duration = 1.5
effects = ["gravity", "wind_drag", "buoyancy"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[fluid]
grain_density = 2.65
[wind]
model = "fixed"
u_star = 0.0
bed_level = 0.0
update_interval = 0.01
[[bodies]]
radius = 0.0125
density = 0.0442
position = [0.0, 500.0]
)toml";
  const Scene s = parse_scene(scene, "<falling>");
  dem::World w(s);
  w.advance_to(1.5);
  const double g = 981 * (1 - 0.00123 / 2.65);
  double lo = 0, hi = 1000;
  for (int k = 0; k < 100; ++k) {
    const double v = 0.5 * (lo + hi);
    (fluid::drag_rate(WindSpec::DragLaw::Thesis, s.fluid, 0.025, v) * v < g ? lo : hi) = v;
  }
  EXPECT_NEAR(-w.particles().vy[0], lo, 0.002 * lo);  // 1.5 s is ~10 response times
  EXPECT_GT(lo, 100);  // not a test of nothing: 0.25 mm sand falls at about 1.9 m/s
  EXPECT_LT(lo, 300);
}

TEST(WindEngine, CheckpointResumesBitwise) {
  const Scene s = parse_scene(windy_scene(), "<windy>");
  dem::World straight(s);
  for (int k = 0; k < 3000; ++k) straight.step();
  dem::World first(s);
  for (int k = 0; k < 1500; ++k) first.step();
  const auto tables = dem::state_tables(first.save_state(), "state/");
  std::map<std::string, SampleTable> by_name;
  for (const SampleTable& t : tables) by_name[t.name] = t;
  dem::World second(s);
  second.restore_state(dem::state_from_tables(by_name, "state/"));
  for (int k = 1500; k < 3000; ++k) second.step();
  ASSERT_GT(straight.wind()->snapshot().updates, 10);
  EXPECT_EQ(straight.wind()->snapshot().u, second.wind()->snapshot().u);
  for (std::size_t i = 0; i < straight.particles().size(); ++i) {
    EXPECT_EQ(straight.particles().x[i], second.particles().x[i]);
    EXPECT_EQ(straight.particles().vx[i], second.particles().vx[i]);
  }
}

TEST(WindEngine, ThreeDRefusesWindDrag) {
  const std::string scene = R"toml([scene]
dimension = 3
duration = 0.1
effects = ["gravity", "wind_drag"]
[fluid]
grain_density = 2.65
[wind]
u_star = 40.0
[[bodies]]
shape = "sphere"
radius = 0.0125
density = 2.65
position = [0.0, 0.0, 1.0]
)toml";
  const Scene s = parse_scene(scene, "<3d>");
  EXPECT_THROW(dem::World3d w(s), InputError);
}
