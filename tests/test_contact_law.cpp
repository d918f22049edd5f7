#include <gtest/gtest.h>

#include <cmath>

#include "contact_law.hpp"

using namespace grainlab;
using namespace grainlab::dem;

TEST(ContactLaw, Table21DampingConventionGivesThesisRestitution) {
  // Digest: Table 2.1's damping 1000 reproduces eps = 0.671 only as a force coefficient (g/s).
  const double meff = 2 * M_PI / 2;  // two r = 1 cm discs, density 2 g/cm^2
  EXPECT_NEAR(restitution_from_damping(5e6, 1000.0, meff), 0.6706, 5e-5);
  // Read as a rate on the reduced mass (gamma m_eff with gamma = 1000 1/s) it would be 0.258.
  EXPECT_NEAR(restitution_from_damping(5e6, 1000.0 * meff, meff), 0.258, 1e-3);
}

TEST(ContactLaw, RestitutionInversionRoundTrips) {
  for (double eps : {0.1, 0.5, 0.85, 0.99})
    for (double meff : {0.01, 1.0, 300.0})
      EXPECT_NEAR(restitution_from_damping(6e9, damping_for_restitution(6e9, eps, meff), meff), eps, 1e-12);
}

TEST(ContactLaw, RestitutionMaterialIsIndependentOfMass) {
  Material m{"sand", 1e6, {Damping::Kind::Restitution, 0.7}, 0, {}, 0};
  const ContactLaw L = contact_law(m, false);
  for (double meff : {0.1, 5.0, 80.0})
    EXPECT_NEAR(restitution_from_damping(1e6, L.normal.coefficient(meff), meff), 0.7, 1e-12);
}

TEST(ContactLaw, ShearForceIsCappedAndTheSpringAnchorSlides) {
  ContactLaw L;
  L.k_s = 100;
  L.mu = 0.5;
  double xi = 0;
  // Small extension: pure spring.
  EXPECT_DOUBLE_EQ(shear_force(L, 10.0, 1.0, 0.0, 0.01, xi), -1.0);
  EXPECT_DOUBLE_EQ(xi, 0.01);
  // Large extension: capped at mu f_n, and the spring shortened so that it equals the cap.
  xi = 0;
  EXPECT_DOUBLE_EQ(shear_force(L, 10.0, 1.0, 0.0, 1.0, xi), -5.0);
  EXPECT_DOUBLE_EQ(-L.k_s * xi, -5.0);
  // No normal force, no friction.
  xi = 0;
  EXPECT_DOUBLE_EQ(shear_force(L, -1.0, 1.0, 0.0, 1.0, xi), 0.0);
}

TEST(ContactLaw, AttractiveNormalForceClippedOnlyWhenAsked) {
  ContactLaw L;
  L.k_n = 10;
  EXPECT_DOUBLE_EQ(normal_force(L, 0.1, 5.0, 1.0), -4.0);  // separating fast: net attraction
  L.clip_attractive = true;
  EXPECT_DOUBLE_EQ(normal_force(L, 0.1, 5.0, 1.0), 0.0);
}

TEST(ContactLaw, RestitutionZeroIsCriticalDamping) {
  // eps -> 0 needs L = -ln eps -> infinity; the limit of 2 L sqrt(k m) / sqrt(pi^2 + L^2) is 2 sqrt(k m),
  // critical damping, where the linear contact no longer rebounds.
  const double k = 1e8, m = 3.0;
  EXPECT_DOUBLE_EQ(damping_for_restitution(k, 0.0, m), 2 * std::sqrt(k * m));
  EXPECT_EQ(restitution_from_damping(k, damping_for_restitution(k, 0.0, m), m), 0.0);
  EXPECT_LT(damping_for_restitution(k, 1e-9, m),
            damping_for_restitution(k, 0.0, m));  // approached from below
}
