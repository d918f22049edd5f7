// The 3-D broad phase: every overlapping pair is among a body's candidates, in ascending order, even with
// a stray body far from the rest (the grid grows its cells rather than its size).
#include <gtest/gtest.h>

#include <algorithm>

#include "domain.hpp"
#include "rng.hpp"
#include "sphere_cells.hpp"

namespace grainlab::dem {

TEST(SphereCells, CandidatesHoldEveryOverlappingPairInAscendingOrder) {
  Rng rng(5, 0);
  std::vector<Vec3> x;
  std::vector<double> r;
  for (int i = 0; i < 600; ++i) {
    x.emplace_back(rng.uniform(0, 30), rng.uniform(0, 30), rng.uniform(0, 10));
    r.push_back(rng.uniform(0.5, 1.5));
  }
  x.emplace_back(1e6, -1e6, 3e5), r.push_back(1.0);  // far away
  SphereCells cells;
  cells.build(x, 1.5, 0.3);
  EXPECT_FALSE(cells.stale(x));
  // Every body moves a little less than half the skin: the lists must still hold every overlap.
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += Vec3(0.08, -0.08, 0.08) * (i % 2 ? 1 : -1);
  EXPECT_FALSE(cells.stale(x));
  std::size_t overlapping = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const std::vector<std::size_t> after(cells.begin(i), cells.end(i));
    EXPECT_TRUE(std::is_sorted(after.begin(), after.end()));
    for (std::size_t j : after) EXPECT_GT(j, i);
    for (std::size_t j = i + 1; j < x.size(); ++j)
      if ((x[i] - x[j]).norm() < r[i] + r[j]) {
        ++overlapping;
        EXPECT_TRUE(std::binary_search(after.begin(), after.end(), j)) << i << " " << j;
      }
  }
  EXPECT_GT(overlapping, 500u);  // the test means something
  x[3] += Vec3(0.2, 0, 0);       // past half the skin
  EXPECT_TRUE(cells.stale(x));
}

}  // namespace grainlab::dem

// Cuts by shares: ten points of weight 1 at x = 0..9 split 0.3 / 0.7 fall between the third and fourth
// point, and equal shares give the equal cut; ties in x are broken by id, the same on every rank.
TEST(WeightedCuts, SplitTheWeightInTheGivenShares) {
  std::vector<double> points;
  for (int i = 0; i < 10; ++i) points.insert(points.end(), {double(i), 1.0, double(i)});
  EXPECT_EQ(grainlab::dem::weighted_cuts(points, 2), std::vector<double>{4.5});
  EXPECT_EQ(grainlab::dem::weighted_cuts(points, 2, {0.5, 0.5}), std::vector<double>{4.5});
  EXPECT_EQ(grainlab::dem::weighted_cuts(points, 2, {0.3, 0.7}), std::vector<double>{2.5});
  EXPECT_EQ(grainlab::dem::weighted_cuts(points, 3, {0.2, 0.5, 0.3}), (std::vector<double>{1.5, 6.5}));
  // Shares of the wrong length are ignored: equal shares.
  EXPECT_EQ(grainlab::dem::weighted_cuts(points, 2, {1.0}), std::vector<double>{4.5});
}
