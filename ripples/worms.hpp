#pragma once
// Haff's worm model of ripple mergers (thesis Ch. V section 2, Fig. 5.16): worms of whole links on a ring;
// each step a worm of length l advances one link with probability A / l. A worm that moves while the worm
// ahead stays eats that worm's last link; a worm that loses its last link has merged. Two worms form a
// Markov chain in one worm's length, absorbing at 0 and L (a merger).
#include <cstdint>
#include <vector>

namespace grainlab::ripples {

// The (L+1) x (L+1) row-stochastic transition matrix of two worms of L links in all, row-major; state i is
// one worm's length. Throws std::invalid_argument unless 0 < A <= 1 and L >= 2.
std::vector<double> worm_chain_matrix(int links, double A);

struct WormChainResult {
  double absorbed = 0;          // probability that the worms have merged by `steps`
  double mean_links_moved = 0;  // expected links one worm advances up to then (A / l per step while alive)
  std::vector<double> absorbed_by_step;  // cumulative, steps 0..N
};
// Exact: the start state pushed through the chain N times.
WormChainResult worm_chain(int links, int start, double A, int steps);

// The same two worms simulated step by step (the rule, not the matrix), `runs` times with Rng(seed, run):
// how many merged by `steps`.
std::size_t worm_pair_merges(int links, int start, double A, int steps, std::size_t runs, std::uint64_t seed);

struct WormRingResult {
  std::vector<int> lengths;         // the surviving worms at the end
  std::vector<double> mean_length;  // after each recorded step
  std::vector<int> recorded_steps;
};
// n worms of `length` links each on a ring, `steps` steps; the mean length is recorded `records` times.
WormRingResult worm_ring(int worms, int length, double A, int steps, std::uint64_t seed, int records = 50);

// Links a worm of length l advances in n steps: mean n A / l, s.d. sqrt(n (A/l)(1 - A/l)) (binomial).
struct Fluctuation {
  double mean = 0, sd = 0;
};
Fluctuation worm_advance(int n, double A, int length);

}  // namespace grainlab::ripples
