// The Ch. V analysis tools on surfaces with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "surface_analysis.hpp"

namespace grainlab::ripples {

namespace {
std::vector<double> sine(int n, double wavelength, double amplitude) {
  std::vector<double> h(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    h[static_cast<std::size_t>(i)] = amplitude * std::sin(2 * M_PI * i / wavelength);
  return h;
}
}  // namespace

TEST(SurfaceAnalysis, WavelengthOfASineThreeWays) {
  const std::vector<double> h = sine(1000, 50, 4);
  EXPECT_DOUBLE_EQ(autocorrelation_wavelength(h), 50);
  const std::vector<double> p = power_spectrum(h);
  EXPECT_EQ(std::max_element(p.begin(), p.end()) - p.begin() + 1, 1000 / 50);
  EXPECT_EQ(length_scale_peak(length_scale_distribution(h, 120, 0.5)), 50);
  // Whole periods of a sine of amplitude a about any level: rms a / sqrt 2.
  std::vector<double> raised = h;
  for (double& v : raised) v += 7;
  EXPECT_NEAR(rms_height(raised), 4 / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(rms_height({}), 0);
}

TEST(SurfaceAnalysis, TombrelloSmoothingKeepsAStepAndCalmsNoise) {
  std::vector<double> h(200, 0.0);
  for (std::size_t i = 100; i < 200; ++i) h[i] = 10;
  for (std::size_t i = 0; i < h.size(); i += 2) h[i] += 0.3;  // a small zig-zag on both levels
  const std::vector<double> s = tombrello_smooth(h, 4, 1.0);
  EXPECT_NEAR(s[99], 0.15, 0.05);  // the foot of the step stays at its level
  EXPECT_NEAR(s[100], 10.15, 0.05);
  EXPECT_LT(std::abs(s[50] - s[51]), 0.1);  // the zig-zag (0.3) is smoothed away
}

}  // namespace grainlab::ripples
