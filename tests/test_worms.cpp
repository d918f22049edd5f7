// Haff's worm model (thesis Ch. V section 2): the two-worm chain against its rule and the spec's numbers.
#include <gtest/gtest.h>

#include <cmath>

#include "worms.hpp"

using namespace grainlab::ripples;

TEST(WormChain, MatrixIsStochasticWithAbsorbingEnds) {
  const int L = 10;
  const std::vector<double> T = worm_chain_matrix(L, 0.6);
  for (int i = 0; i <= L; ++i) {
    double row = 0;
    for (int j = 0; j <= L; ++j) {
      row += T[i * (L + 1) + j];
      EXPECT_GE(T[i * (L + 1) + j], 0);
    }
    EXPECT_NEAR(row, 1, 1e-15);
  }
  EXPECT_EQ(T[0], 1);
  EXPECT_EQ(T[(L + 1) * (L + 1) - 1], 1);
  EXPECT_THROW(worm_chain_matrix(10, 1.5), std::invalid_argument);
}

TEST(WormChain, TwoFiveLinkWormsRarelyMerge) {
  // Spec: two 5-link worms merge with probability ~0.05 after moving ~50 links for A near 0.6; A = 1
  // makes merging impossible (a 1-link worm always moves, so it is never eaten).
  const WormChainResult r = worm_chain(10, 5, 0.6, 416);
  EXPECT_NEAR(r.mean_links_moved, 50, 5);
  EXPECT_NEAR(r.absorbed, 0.05, 0.01);
  EXPECT_EQ(worm_chain(10, 5, 1.0, 2000).absorbed, 0.0);
  // Merging gets likelier as A falls.
  EXPECT_GT(worm_chain(10, 5, 0.5, 416).absorbed, r.absorbed);
}

TEST(WormChain, MonteCarloOfTheRuleAgreesWithTheMatrix) {
  // The rule simulated step by step and the chain's exact absorption agree within the 99.9 % interval.
  for (const double A : {0.5, 0.7}) {
    const std::size_t runs = 20000;
    const double exact = worm_chain(10, 4, A, 300).absorbed;
    const double mc = double(worm_pair_merges(10, 4, A, 300, runs, 7)) / runs;
    EXPECT_NEAR(mc, exact, 3.29 * std::sqrt(exact * (1 - exact) / runs)) << "A " << A;
  }
}

TEST(WormRing, MergingStopsNearTenLinks) {
  // From 2-link worms, merging stops near ~10 links (thesis, A below 1); with A = 1 nothing merges.
  const WormRingResult r = worm_ring(200, 2, 0.6, 200000, 3);
  EXPECT_GT(r.mean_length.back(), 7);
  EXPECT_LT(r.mean_length.back(), 15);
  int total = 0;
  for (int l : r.lengths) total += l;
  EXPECT_EQ(total, 400);  // links are conserved
  EXPECT_EQ(worm_ring(200, 2, 1.0, 20000, 3).lengths.size(), 200u);
}

TEST(WormAdvance, BinomialFluctuation) {
  // n = 100, A = 1, l = 10: 10 +- 3.
  const Fluctuation f = worm_advance(100, 1.0, 10);
  EXPECT_DOUBLE_EQ(f.mean, 10);
  EXPECT_NEAR(f.sd, 3, 0.01);
}
