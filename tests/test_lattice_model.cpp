// The lattice-bed model (thesis Fig. 5.21): the lattice's geometry holds under every move, grains are
// conserved, and the thesis's qualitative claims: brink ejection leaves a close-packed surface nearly flat,
// target ejection roughens it into a ripple-like population.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "lattice_model.hpp"
#include "ripple_config.hpp"

namespace grainlab::ripples {

namespace {
LatticeParams params(double brink, double roughness) {
  LatticeParams p;
  p.columns = 2000, p.brink_probability = brink, p.roughness = roughness, p.forward = 15, p.backward = 5;
  return p;
}
}  // namespace

TEST(LatticeModel, SurfaceStaysAtTheReposeAngleAndGrainsAreConserved) {
  LatticeModel m(params(0.5, 0.3));
  const long grains = m.grains();
  m.fire(20000);
  const auto& h = m.heights();
  for (std::size_t i = 0; i < h.size(); ++i) ASSERT_EQ(std::abs(h[i] - h[(i + 1) % h.size()]), 1) << i;
  EXPECT_EQ(m.grains(), grains);
  EXPECT_EQ(m.impacts(), 20000);
  EXPECT_GT(m.backward_hops(), 0);  // grazing paths hit some grains on their downstream side
  EXPECT_GT(m.forward_hops(), 10 * m.backward_hops());
}

// Narrow domains take the slope bits' slow path (several wrapped copies of each column), and long runs
// dig troughs below the initial bed's datum: neither may break the lattice or lose grains.
TEST(LatticeModel, NarrowDomainsAndDeepTroughsKeepTheLattice) {
  for (const bool downhill : {false, true}) {
    LatticeParams p;
    p.columns = 40, p.forward = 6, p.backward = 2, p.brink_lookahead = 5, p.depth = 0, p.roughness = 0.5;
    p.land_downhill = downhill;
    LatticeModel m(p);
    const long grains = m.grains();
    m.fire(200000);
    const auto& h = m.heights();
    for (std::size_t i = 0; i < h.size(); ++i) ASSERT_EQ(std::abs(h[i] - h[(i + 1) % h.size()]), 1) << i;
    EXPECT_EQ(m.grains(), grains);
    EXPECT_LT(*std::min_element(h.begin(), h.end()), 0);  // the troughs went below the start's layer 0
  }
}

TEST(LatticeModel, BrinkEjectionKeepsTheSurfaceFlatTargetEjectionRoughensIt) {
  LatticeModel brink(params(1.0, 0.5)), target(params(0.0, 0.5));
  const double start = lattice_surface_stats(brink.heights()).rms;
  brink.fire(20000), target.fire(20000);  // 20 ejections per surface grain
  EXPECT_LT(lattice_surface_stats(brink.heights()).rms, 1.5 * start);
  EXPECT_GT(lattice_surface_stats(target.heights()).rms, 3 * start);
  LatticeModel flat(params(1.0, 0.0));  // nothing is a brink on a close-packed top: nothing moves
  const std::vector<int> before = flat.heights();
  flat.fire(5000);
  EXPECT_EQ(flat.heights(), before);
}

TEST(LatticeModel, SurfaceStatisticsOfATriangleWave) {
  // Rises of 30 columns and falls of 30 at the repose angle: period 60 columns = 30 lattice spacings,
  // crest-to-trough 30 layers, both flanks at 30 deg.
  std::vector<int> h;
  for (int period = 0; period < 10; ++period)
    for (int k = 0; k < 60; ++k) h.push_back(100 + (k < 30 ? k : 60 - k));
  const LatticeSurfaceStats s = lattice_surface_stats(h, 0);
  EXPECT_NEAR(s.wavelength, 30, 1e-9);
  EXPECT_NEAR(s.height, 30, 1e-9);
  EXPECT_NEAR(s.stoss_deg, 30, 1e-6);
  EXPECT_NEAR(s.lee_deg, 30, 1e-6);
}

TEST(LatticeModel, SameSeedSameSurface) {
  LatticeModel a(params(0.5, 0.2)), b(params(0.5, 0.2));
  a.fire(3000);
  b.fire(1000), b.fire(2000);
  EXPECT_EQ(a.heights(), b.heights());
}

// A seeded sine is a valid lattice walk whose mode has the asked amplitude (to the walk's rounding), and
// nothing else of size: the rest of the surface is the zig-zag.
TEST(LatticeModel, SeededSineIsTheNearestWalk) {
  LatticeParams p = params(0.0, 0.0);
  p.initial_amplitude = 3, p.initial_wavelength = 100;  // 2000 columns: 10 waves
  LatticeModel m(p);
  const auto& h = m.heights();
  for (std::size_t i = 0; i < h.size(); ++i) ASSERT_EQ(std::abs(h[i] - h[(i + 1) % h.size()]), 1) << i;
  EXPECT_EQ(lattice_seeded_waves(p), 10);
  const std::complex<double> a = lattice_mode(h, 10);
  EXPECT_NEAR(std::abs(a), 3, 0.1);
  EXPECT_NEAR(std::arg(a), -M_PI / 2, 0.05);  // a sine: h = 3 sin(k x) = Re(-3 i exp(i k x))
  EXPECT_LT(std::abs(lattice_mode(h, 20)), 0.1);
  p.initial_amplitude = 40;  // steeper than 30 deg: not a walk
  EXPECT_THROW(LatticeModel{p}, std::invalid_argument);
}

// The finite-hop theory: Re s = c k [(1 - b) sin k L_f - b sin k L_b], zero where the forward hop is a
// whole wavelength (and b = 0), negative past half a wavelength; and a seeded long wave does grow at it.
TEST(LatticeModel, LinearResponseFollowsTheFiniteHopTheory) {
  EXPECT_NEAR(lattice_linear_rate(15, 15, 5, 0, 15).real(), 0, 1e-12);
  EXPECT_LT(lattice_linear_rate(15, 15, 5, 0, 20).real(), 0);
  const double c = 1 / (2 * std::sqrt(3.0) * std::tan(15 * M_PI / 180)), k = 2 * M_PI / 100;
  EXPECT_NEAR(lattice_linear_rate(15, 15, 5, 0, 100).real(), c * k * std::sin(15 * k), 1e-12);
  EXPECT_NEAR(lattice_linear_rate(15, 15, 5, 0, 100).imag(), -k * c * (1 - std::cos(15 * k)), 1e-12);
  LatticeParams p = params(0.0, 0.0);
  p.initial_amplitude = 2, p.initial_wavelength = 100;
  const LatticeResponse r = lattice_linear_response(p, 4, 8, 6);
  EXPECT_NEAR(r.growth, r.theory_growth, 0.15 * r.theory_growth);  // 6 seeds: wider than the suite's 20
  EXPECT_GT(r.speed, 0);                                           // downstream
}

TEST(LatticeConfig, RejectsBadValuesWithFileAndKey) {
  EXPECT_THROW(parse_lattice_config("[lattice]\ncolumns = 101\n", "x.toml"), std::exception);
  EXPECT_THROW(parse_lattice_config("[lattice]\nbrink_probability = 1.5\n", "x.toml"), std::exception);
  EXPECT_THROW(parse_lattice_config("[lattice]\nunknown = 1\n", "x.toml"), std::exception);
  // Wind mode needs recorded ejecta to fly: no file, or the sand gun's moments, is refused.
  EXPECT_THROW(parse_lattice_config("[lattice]\nsplash_wind = 40.0\n", "x.toml"), std::exception);
  EXPECT_THROW(parse_lattice_config("[lattice]\nsplash = \"sand-gun\"\nsplash_wind = 40.0\n", "x.toml"),
               std::exception);
  EXPECT_EQ(parse_lattice_config("[lattice]\nsplash = \"s.h5\"\nsplash_wind = 40.0\n", "x.toml").splash_wind,
            40);
  EXPECT_THROW(parse_lattice_config("[bins]\n", "x.toml"), std::exception);
  EXPECT_THROW(parse_lattice_config("[lattice]\ninitial_amplitude = 2\n", "x.toml"), std::exception);
  EXPECT_THROW(parse_lattice_config(
                   "[lattice]\ninitial_amplitude = 2\ninitial_wavelength = 50\nroughness = 0.1\n", "x.toml"),
               std::exception);
  EXPECT_THROW(parse_lattice_config("[lattice]\ninitial_amplitude = 40\ninitial_wavelength = 20\n", "x.toml"),
               std::exception);
  const LatticeRun r = parse_lattice_config("[lattice]\nforward = 4\nbackward = 0\n", "x.toml");
  EXPECT_EQ(r.params.forward, 4);
  EXPECT_EQ(r.params.backward, 0);
}

}  // namespace grainlab::ripples
