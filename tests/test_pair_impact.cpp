// Grain-pair impacts at the Ch. III scale on every engine: the building blocks of the pair-impact study.
#include <gtest/gtest.h>

#include "engine.hpp"
#include "pair_impact.hpp"

using namespace grainlab::validation;

TEST(PairImpact, HeadOnRestitutionIsTheMaterials) {
  for (int dim : {2, 3})
    for (const std::string& engine : grainlab::engines_for_dimension(dim))
      for (double speed : {1000.0, 8100.0})
        EXPECT_NEAR(pair_impact(engine, dim, speed, 0.0).normal_restitution, 0.85, 0.01)
            << engine << " " << dim << "-D at " << speed << " cm/s";
}

TEST(PairImpact, ImpulseEnginesSlideAsWaltonAtGrazingIncidence) {
  // At 85 deg the contact slides throughout: beta = -1 + mu (1 + e)(1 + 1/K) cot(angle), with the
  // normal restitution the engine actually produced.
  for (int dim : {2, 3})
    for (const std::string& engine : grainlab::engines_for_dimension(dim)) {
      if (grainlab::engine_capabilities(engine).soft_contacts)
        continue;  // a soft contact turns during a grazing impact (docs/validation.md)
      const PairImpactResult r = pair_impact(engine, dim, 1000.0, 85.0);
      EXPECT_NEAR(r.tangential_restitution,
                  walton_sliding_beta(0.5, r.normal_restitution, dim == 2 ? 0.5 : 0.4, 85.0), 0.01)
          << engine << " " << dim << "-D";
    }
}

TEST(PairImpact, NativeSlidesAsWaltonAndReboundsTangentiallyWhenItSticks) {
  // Sliding throughout (85 deg): Walton's sliding value at the impact's own angle.
  for (int dim : {2, 3}) {
    const PairImpactResult r = pair_impact("native", dim, 1000.0, 85.0);
    EXPECT_NEAR(r.tangential_restitution,
                walton_sliding_beta(0.5, 0.85, dim == 2 ? 0.5 : 0.4, r.impact_angle_deg), 0.01);
  }
  // Sticking (45 deg): the shear spring gives tangential motion back, so the contact point reverses
  // (beta > 0) where an impulse engine stops it (beta = 0).
  EXPECT_GT(pair_impact("native", 2, 1000.0, 45.0).tangential_restitution, 0.2);
  EXPECT_NEAR(pair_impact("box2d", 2, 1000.0, 45.0).tangential_restitution, 0.0, 0.01);
}
