// The continuum surface evolution (thesis Ch. V section 1): the finite-difference solver's growth rates
// against the anti-diffusion equation's.
#include <gtest/gtest.h>

#include <cmath>

#include "continuum.hpp"

using namespace grainlab::ripples;

TEST(Continuum, ImpactFluxOnASlope) {
  // Eq. 5.6: a slope facing the impacts (up in x) catches more, the lee less; zero at the shadow slope.
  EXPECT_DOUBLE_EQ(impact_flux_on_slope(0, 10), 1.0);
  EXPECT_GT(impact_flux_on_slope(0.1, 10), 1.0);
  EXPECT_LT(impact_flux_on_slope(-0.1, 10), 1.0);
  EXPECT_NEAR(impact_flux_on_slope(-std::tan(10 * M_PI / 180), 10), 0.0, 1e-12);
}

TEST(Continuum, SmallUndulationsGrowAtTheAntiDiffusionRate) {
  // A tiny sine grows per step by 1 + dt D (2 - 2 cos(k dx)) / dx^2 (D = a d^2 F_x / tan alpha): the
  // discrete form of sigma = D k^2. Tested for three wavelengths; shorter ones grow faster.
  ContinuumParams p;
  const int n = 64, steps = 200;
  double last = 0;
  for (const int waves : {1, 2, 4}) {
    const double k = 2 * M_PI * waves / (n * p.dx);
    std::vector<double> h(n);
    for (int i = 0; i < n; ++i) h[i] = 1e-9 * std::sin(k * i * p.dx);
    advance_continuum(p, h, steps);
    double amp = 0;  // projection on the sine
    for (int i = 0; i < n; ++i) amp += 2.0 / n * h[i] * std::sin(k * i * p.dx);
    const double measured = std::pow(amp / 1e-9, 1.0 / steps), predicted = continuum_growth_per_step(p, k);
    EXPECT_NEAR(measured, predicted, 1e-9) << waves;
    EXPECT_GT(predicted, 1.0);
    EXPECT_GT(predicted, last);
    last = predicted;
    // The continuum limit: sigma -> D k^2 as dx -> 0.
    EXPECT_NEAR((predicted - 1) / p.dt, p.anti_diffusivity() * k * k, 0.02 * p.anti_diffusivity() * k * k);
  }
}

TEST(Continuum, SandIsConserved) {
  ContinuumParams p;
  std::vector<double> h(50);
  for (int i = 0; i < 50; ++i) h[i] = 0.05 * std::sin(0.3 * i) + 0.01 * std::cos(1.1 * i);
  double before = 0, after = 0;
  for (double x : h) before += x;
  advance_continuum(p, h, 100);
  for (double x : h) after += x;
  EXPECT_NEAR(after, before, 1e-12);
}

namespace grainlab::ripples {

TEST(Continuum, SteadyShapesAreFlatOrSteepenExponentially) {
  // Eq. 5.7 integrated numerically reproduces the closed form 5.8 from any start; the flat shape sits at
  // h0 + lambda tan(alpha), and a start above it steepens downstream, one below falls away.
  ContinuumParams p;
  const double v = 0.1, h0 = 0, lambda = steady_length(p, v);
  const double flat = lambda * std::tan(p.alpha_deg * M_PI / 180);
  EXPECT_NEAR(lambda, p.a * p.d * p.d * p.F_x / (v * std::tan(p.alpha_deg * M_PI / 180)), 1e-12);
  const double ds = lambda / 200;
  for (const double C : {-0.01, 0.0, 0.01}) {
    const std::vector<double> h = integrate_steady_shape(p, v, h0, flat + C, ds, 600);
    for (std::size_t i = 0; i < h.size(); i += 50)
      EXPECT_NEAR(h[i], steady_shape(p, v, C, h0, i * ds), 1e-9 * (1 + std::abs(h[i]))) << C << " " << i;
  }
  // Anti-diffusion carries the exponential at exactly v: dh/dt = -v h' and -D h'' agree when lambda = D / v.
  EXPECT_NEAR(p.anti_diffusivity() / (lambda * lambda), v / lambda, 1e-12);
}

}  // namespace grainlab::ripples
