// The loaded-die model of thesis Appendix II.1 against the geometry of the die itself.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include "die_model.hpp"
#include "ensemble.hpp"
#include "loaded_die.hpp"

using namespace grainlab::validation;

// A fair die has no preference whatever the restitution (the thesis: p_h = 1/2).
TEST(DieModel, FairDieIsFair) {
  for (double eps : {0.0, 0.3, 0.7, 0.99}) {
    EXPECT_DOUBLE_EQ(die_model(0, eps, DieModelVariant::Printed).p_h, 0.5);
    EXPECT_DOUBLE_EQ(die_model(0, eps, DieModelVariant::Geometric).p_h, 0.5);
  }
}

// The barriers are the heights the centre of mass climbs when the die pivots over each corner: with
// half-side a = 1 and the centre of mass at (f, f), a low face is 1 - f below it and a high face 1 + f;
// the corners are sqrt2 (1 - f), sqrt2 sqrt(1 + f^2) and sqrt2 (1 + f) away.
TEST(DieModel, BarriersAreTheGeometryOfTheDie) {
  for (double f : {0.1, 0.25, 0.5}) {
    const double cx = f, cy = f;
    auto dist = [&](double x, double y) { return std::hypot(x - cx, y - cy); };
    const double low_rest = 1 - f, high_rest = 1 + f;
    const DieModel g = die_model(f, 0.7, DieModelVariant::Geometric);
    EXPECT_NEAR(g.e_low, dist(1, 1) - low_rest, 1e-14);
    EXPECT_NEAR(g.e_mid, dist(1, -1) - low_rest, 1e-14);
    EXPECT_NEAR(g.e_high, dist(-1, -1) - low_rest, 1e-14);
    EXPECT_NEAR(g.high_well, high_rest - low_rest, 1e-14);
    // As printed, E_l and E_M are these, but the high-face wells sit at f and E_h is f lower.
    const DieModel p = die_model(f, 0.7, DieModelVariant::Printed);
    EXPECT_DOUBLE_EQ(p.e_low, g.e_low);
    EXPECT_DOUBLE_EQ(p.e_mid, g.e_mid);
    EXPECT_NEAR(g.e_high - p.e_high, f, 1e-14);
    EXPECT_NEAR(p.high_well, f, 1e-14);
  }
}

// Eq. 2.A.2's worked example: with E_l = 0.29, E_M = 0.78 (f = 0.3), eps = 0.9, the 90 deg window is
// min(E_M / eps^2, E_l / eps^4) - E_l.
TEST(DieModel, NinetyDegreeWindowIsEq2A2) {
  const DieModel d = die_model(0.3, 0.9, DieModelVariant::Printed);
  const double e2 = 0.81;
  EXPECT_NEAR(d.window[1], std::min(d.e_mid / e2, d.e_low / (e2 * e2)) - d.e_low, 1e-12);
  EXPECT_NEAR(d.window[0], std::max(0.0, d.e_low / e2 - d.e_mid), 1e-12);  // closed here: 0
}

// With the die's own potential, a loaded die lands low face down (high face up) more often, and more so
// the less energy each collision takes: the thesis's physical reading.
TEST(DieModel, GeometricModelFavoursTheLowFacesMoreAsEpsRises) {
  for (double f : {0.1, 0.3, 0.5}) {
    EXPECT_GT(die_model(f, 0.3, DieModelVariant::Geometric).p_h, 0.5);
    EXPECT_GE(die_model(f, 0.9, DieModelVariant::Geometric).p_h,
              die_model(f, 0.3, DieModelVariant::Geometric).p_h);
  }
}

// The 95 % Wilson interval for 50 of 100 is [0.4038, 0.5962]; for 0 of 10 it is [0, 0.2775].
TEST(Ensemble, WilsonIntervalKnownValues) {
  const Proportion half = wilson_interval(50, 100);
  EXPECT_NEAR(half.lo, 0.40383, 1e-5);
  EXPECT_NEAR(half.hi, 0.59617, 1e-5);
  const Proportion none = wilson_interval(0, 10);
  EXPECT_DOUBLE_EQ(none.lo, 0.0);
  EXPECT_NEAR(none.hi, 0.27753, 1e-5);
  EXPECT_EQ(throws_for_half_width(0.5, 0.02), 2401);
}

// Student's t quantiles from a table (t_0.975): 12.706 (1 dof), 2.776 (4), 2.262 (9), 2.093 (19), 1.960
// (infinity). The interval of 1..5 is 3 -+ 2.776 x 1.5811 / sqrt(5) = 3 -+ 1.963, where 1.96 would
// give 1.386.
TEST(Ensemble, MeanIntervalUsesStudentsT) {
  EXPECT_NEAR(t_975(1), 12.706, 5e-4);
  EXPECT_NEAR(t_975(4), 2.776, 5e-4);
  EXPECT_NEAR(t_975(9), 2.262, 5e-4);
  EXPECT_NEAR(t_975(19), 2.093, 5e-4);
  EXPECT_NEAR(t_975(1000000), 1.960, 5e-4);
  EXPECT_THROW(t_975(0), std::invalid_argument);
  EXPECT_NEAR(family_t(4, 9), 3.1109, 5e-4);  // t_0.99375, 9 dof (Bonferroni over 4), by quadrature apart
  EXPECT_NEAR(family_t(4, 1000000), family_z(4), 1e-4);
  const MeanInterval m = mean_interval({1, 2, 3, 4, 5, std::nan("")});
  EXPECT_EQ(m.n, 5u);
  EXPECT_DOUBLE_EQ(m.mean, 3);
  EXPECT_NEAR(m.half_width(), 1.963, 5e-4);
  const MeanInterval one = mean_interval({7});
  EXPECT_EQ(one.sd, 0);
  EXPECT_EQ(one.lo, one.hi);
}

// An ensemble tells its progress before its first run as well as after each, so that a progress bar
// has a start to time the first run from ("left 0m00s" until the second run otherwise).
TEST(Ensemble, ProgressIsToldFromTheStart) {
  std::vector<std::pair<std::size_t, std::size_t>> told;
  run_ensemble(
      3, 1, [](std::size_t i) { return std::vector<double>{double(i)}; },
      [&](std::size_t done, std::size_t total) { told.emplace_back(done, total); });
  const std::vector<std::pair<std::size_t, std::size_t>> expected = {{0, 3}, {1, 3}, {2, 3}, {3, 3}};
  EXPECT_EQ(told, expected);
}

// A throw's outcome depends on (seed, index) alone: the same throw twice is the same, and a fair die
// thrown on the native engine is captured by a face.
TEST(Ensemble, LineFitKnownValues) {
  // On a line exactly: its coefficients and zero errors.
  const LineFit exact = fit_line({0, 1, 2, 3}, {1, 3, 5, 7});
  EXPECT_NEAR(exact.intercept, 1, 1e-12);
  EXPECT_NEAR(exact.slope, 2, 1e-12);
  EXPECT_NEAR(exact.slope_se, 0, 1e-12);
  // x = 0, 1, 2, y = 0, 2, 1 (worked by hand): slope 0.5, intercept 0.5, residuals -0.5, 1, -0.5, so
  // s^2 = 1.5 / 1, slope s.e. = sqrt(1.5 / 2), intercept s.e. = sqrt(1.5 (1/3 + 1/2)).
  const LineFit f = fit_line({0, 1, 2}, {0, 2, 1});
  EXPECT_NEAR(f.slope, 0.5, 1e-12);
  EXPECT_NEAR(f.intercept, 0.5, 1e-12);
  EXPECT_NEAR(f.slope_se, std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(f.intercept_se, std::sqrt(1.5 * (1.0 / 3 + 0.5)), 1e-12);
  EXPECT_THROW(fit_line({1, 1, 1}, {0, 1, 2}), std::invalid_argument);
  EXPECT_THROW(fit_line({0, 1}, {0, 1}), std::invalid_argument);
}

TEST(Ensemble, ThrowsAreReproducible) {
  for (std::size_t i : {0u, 7u}) {
    const DieThrow a = throw_die_2d("native", Die2d{0.0, 0.7, 0.8}, 5, i),
                   b = throw_die_2d("native", Die2d{0.0, 0.7, 0.8}, 5, i);
    EXPECT_EQ(a.face_down, b.face_down);
    EXPECT_EQ(a.time, b.time);
    EXPECT_GE(a.face_down, 0);
  }
}

// The drilled die: removing more mass from the faces with more pips moves the centre of mass toward
// the one (-z), the two (-y) and the three (-x), in proportion to 6 - 1, 5 - 2 and 4 - 3 pips.
TEST(LoadedDie3d, DrilledDieLeansTowardTheOne) {
  const Die3d d = drilled_die(0.5, 0.8);
  EXPECT_LT(d.com[2], 0);
  EXPECT_LT(d.com[1], 0);
  EXPECT_LT(d.com[0], 0);
  EXPECT_NEAR(d.com[2] / d.com[0], 5.0, 1e-9);
  EXPECT_NEAR(d.com[1] / d.com[0], 3.0, 1e-9);
  EXPECT_NEAR(d.mass, 16.0 - 21 * 2.0 * M_PI * 0.15 * 0.15 * 0.06, 1e-12);
  EXPECT_EQ(die_value(0, 0, -1), 1);
  EXPECT_EQ(die_value(0, 0, 1), 6);
  EXPECT_EQ(die_value(-1, 0, 0) + die_value(1, 0, 0), 7);
}

// Every 3-D engine captures a thrown cube on a face, and the same throw gives the same face twice.
TEST(LoadedDie3d, ThrowsAreCapturedAndReproducible) {
  for (const char* engine : {"native", "ode", "bullet"}) {
    const Die3d fair;
    const DieThrow3d a = throw_die_3d(engine, fair, 3, 1), b = throw_die_3d(engine, fair, 3, 1);
    EXPECT_GE(a.value_up, 1) << engine;
    EXPECT_LE(a.value_up, 6) << engine;
    EXPECT_EQ(a.value_up, b.value_up) << engine;
    EXPECT_EQ(a.time, b.time) << engine;
  }
}
