// The thesis's Ch. II code checks with its published numbers (the `thesis-code` suite reports the same).
#include <gtest/gtest.h>

#include "thesis_checks.hpp"

using namespace grainlab::validation;

TEST(Table21, TightToleranceMatchesEq22Within0p2Percent) {
  const double eps = table21_predicted_restitution();
  EXPECT_NEAR(eps, 0.6706, 1e-4);
  for (double v : {10.0, 500.0, 3000.0})
    EXPECT_NEAR(table21_collision(v, 1e-6).restitution, eps, 0.002 * eps) << v;
}

TEST(Table21, ThesisToleranceMatchesThesisMeasurementsWithin1p5Percent) {
  const std::vector<std::pair<double, double>> thesis = {
      {10, 0.675}, {100, 0.675}, {1000, 0.664}, {3000, 0.674}};
  for (const auto& [v, eps] : thesis) {
    const PairCollision c = table21_collision(v, 0.005);
    EXPECT_NEAR(c.restitution, eps, 0.015 * eps) << v;
    // The thesis resolved a collision in ~36 steps at this tolerance: same order here.
    EXPECT_GT(c.steps_in_contact, 18) << v;
    EXPECT_LT(c.steps_in_contact, 72) << v;
  }
}

TEST(SpinningCircle, RotationalEnergyLossWithinOnePercentOfFormula) {
  const SpinLoss s = spinning_circle_loss(0.005);
  EXPECT_NEAR(s.predicted, 778.0, 0.5);
  EXPECT_NEAR(s.rotational_energy_loss, s.predicted, 0.01 * s.predicted);
}

TEST(Conservation, ElasticGasEnergyDriftBelow1e4WithVerlet) {
  const GasConservation g = elastic_gas(200, 100000, true, 7);
  EXPECT_LT(g.relative_energy_drift, 1e-4);
}

TEST(Conservation, MomentumWithoutWallsAtRoundOff) {
  const GasConservation g = elastic_gas(200, 5000, false, 8);
  EXPECT_LT(g.momentum_error, 1e-12);
}

// One shaken pile's rise time is chaotic (a change in the last bit of a force sum moves it by many
// cycles), so the thesis's claim that friction speeds sorting is tested on an ensemble of jittered piles.
TEST(Sorting, LargeDiscRisesFasterWithFriction) {
  const SortingEnsemble with = gold_pan_ensemble(30, true, 8);
  const SortingEnsemble without = gold_pan_ensemble(30, false, 8);
  EXPECT_GE(with.fraction_risen, 0.5) << "the large disc rose in too few frictional piles";
  EXPECT_GT(with.fraction_risen, without.fraction_risen);
  EXPECT_LT(with.median, without.median);
}
