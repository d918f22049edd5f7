#include "worms.hpp"

#include <cmath>
#include <stdexcept>

#include "rng.hpp"

namespace grainlab::ripples {

namespace {

void check(int links, double A) {
  if (!(A > 0 && A <= 1)) throw std::invalid_argument("worm model: A must lie in (0, 1]");
  if (links < 2) throw std::invalid_argument("worm model: at least 2 links");
}

}  // namespace

std::vector<double> worm_chain_matrix(int L, double A) {
  check(L, A);
  const std::size_t n = static_cast<std::size_t>(L) + 1;
  std::vector<double> T(n * n, 0.0);
  T[0] = 1, T[n * n - 1] = 1;  // merged: absorbing
  for (int i = 1; i < L; ++i) {
    const double p = A / i, q = A / (L - i);  // each worm's chance to move
    const std::size_t r = static_cast<std::size_t>(i) * n;
    T[r + i - 1] = q * (1 - p);            // only the other moved: it eats one of ours
    T[r + i + 1] = p * (1 - q);            // only ours moved: we eat one of its links
    T[r + i] = p * q + (1 - p) * (1 - q);  // both moved, or neither
  }
  return T;
}

WormChainResult worm_chain(int L, int start, double A, int steps) {
  check(L, A);
  if (start < 0 || start > L) throw std::invalid_argument("worm chain: start outside 0..L");
  const std::vector<double> T = worm_chain_matrix(L, A);
  const std::size_t n = static_cast<std::size_t>(L) + 1;
  std::vector<double> p(n, 0.0), next(n);
  p[static_cast<std::size_t>(start)] = 1;
  WormChainResult r;
  r.absorbed_by_step.push_back(p[0] + p[n - 1]);
  for (int s = 0; s < steps; ++s) {
    for (std::size_t i = 1; i + 1 < n; ++i) r.mean_links_moved += p[i] * A / static_cast<double>(i);
    std::fill(next.begin(), next.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = (i > 0 ? i - 1 : 0); j <= std::min(n - 1, i + 1); ++j)
        next[j] += p[i] * T[i * n + j];
    p.swap(next);
    r.absorbed_by_step.push_back(p[0] + p[n - 1]);
  }
  r.absorbed = r.absorbed_by_step.back();
  return r;
}

std::size_t worm_pair_merges(int L, int start, double A, int steps, std::size_t runs, std::uint64_t seed) {
  check(L, A);
  std::size_t merged = 0;
  for (std::size_t run = 0; run < runs; ++run) {
    Rng rng(seed, run);
    int a = start;  // the other worm has L - a links
    for (int s = 0; s < steps && a > 0 && a < L; ++s) {
      const bool ma = rng.uniform() < A / a, mb = rng.uniform() < A / (L - a);
      if (ma && !mb) ++a;  // ours eats the other's last link
      if (mb && !ma) --a;  // and the other way round (on a ring each worm is ahead of the other)
    }
    merged += a == 0 || a == L;
  }
  return merged;
}

WormRingResult worm_ring(int worms, int length, double A, int steps, std::uint64_t seed, int records) {
  check(worms * length, A);
  WormRingResult r;
  std::vector<int> l(static_cast<std::size_t>(worms), length);
  Rng rng(seed, 0);
  std::vector<char> moved;
  const int every = std::max(1, steps / std::max(1, records));
  for (int s = 1; s <= steps && l.size() > 1; ++s) {
    moved.resize(l.size());
    for (std::size_t i = 0; i < l.size(); ++i) moved[i] = rng.uniform() < A / l[i];
    // Each worm that moves while the one ahead (next on the ring) stays takes its last link.
    std::vector<int> change(l.size(), 0);
    for (std::size_t i = 0; i < l.size(); ++i) {
      const std::size_t ahead = (i + 1) % l.size();
      if (moved[i] && !moved[ahead]) ++change[i], --change[ahead];
    }
    std::vector<int> kept;
    for (std::size_t i = 0; i < l.size(); ++i)
      if (l[i] + change[i] > 0) kept.push_back(l[i] + change[i]);
    l.swap(kept);
    if (s % every == 0) {
      double sum = 0;
      for (int x : l) sum += x;
      r.mean_length.push_back(sum / static_cast<double>(l.size()));
      r.recorded_steps.push_back(s);
    }
  }
  r.lengths = l;
  return r;
}

Fluctuation worm_advance(int n, double A, int length) {
  const double p = A / length;
  return {n * p, std::sqrt(n * p * (1 - p))};
}

}  // namespace grainlab::ripples
