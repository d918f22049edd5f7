// The tumbling polygon's analytic pieces: the pivot rule from impulse mechanics, the classifier, and the
// ideal rolling polygon against a limit it must reach.
#include <gtest/gtest.h>

#include <cmath>

#include "tumbling_polygon.hpp"

using namespace grainlab::validation;

TEST(TumblingPolygon, RigidPivotGivesTheClosedFormRule) {
  for (int n = 3; n <= 12; ++n) {
    const double c = std::cos(M_PI / n), icm = (1 + 2 * c * c) / 6, ip = icm + 1;  // per m R^2
    EXPECT_NEAR(pivot_ratio_rigid(n, 0.0), 1 - (1 / ip) * (1 - std::cos(2 * M_PI / n)), 1e-12) << n;
  }
  EXPECT_NEAR(pivot_ratio_rigid(4, 0.0), 0.25, 1e-12);  // the digest's square
  // A bouncier vertex keeps less spin.
  EXPECT_LT(pivot_ratio_rigid(4, 0.5), pivot_ratio_rigid(4, 0.0));
}

TEST(TumblingPolygon, ImpulseEnginesFollowThePivotRule) {
  for (const char* engine : {"box2d", "ode", "bullet"})
    EXPECT_NEAR(pivot_ratio_measured(engine, 4, 0.01, 10.0), 0.25, 0.0125) << engine;
}

TEST(TumblingPolygon, ClassifierOrder) {
  EXPECT_EQ(classify(300, 2.0, 0.9, 4),
            Motion::Rolling);  // turned more than a quarter: rolling, even hopping
  EXPECT_EQ(classify(300, 0.1, 0.5, 4), Motion::Bouncing);
  EXPECT_EQ(classify(0.3, 0.2, 0.0, 4), Motion::Rest);  // rocking in place
  EXPECT_EQ(classify(300, 0.0, 0.0, 4), Motion::Sliding);
}

TEST(TumblingPolygon, IdealRollingSpeedsUpWithSlopeAndStopsBelowTheBarrier) {
  // A square cannot keep rolling at 20 deg (its spin after an impact is 1/4 of the spin before, too
  // little to lift it over 25 deg of barrier); a hexagon can, faster on steeper slopes.
  EXPECT_EQ(ideal_rolling(4, std::sqrt(2.0), 20, 981).speed, 0.0);
  const double h20 = ideal_rolling(6, std::sqrt(2.0), 20, 981).speed,
               h30 = ideal_rolling(6, std::sqrt(2.0), 30, 981).speed;
  EXPECT_GT(h20, 0.0);
  EXPECT_GT(h30, h20);
}
