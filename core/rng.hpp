#pragma once
// Seeded randomness keyed by (seed, run index): a run's numbers do not depend on how runs are spread
// over processes. Distributions are written out here (not std::*_distribution, whose algorithms differ
// between standard libraries) so the same seed gives the same numbers everywhere.
#include <cmath>
#include <cstdint>

namespace grainlab {

class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t run_index = 0)
      : s_(mix(seed ^ mix(run_index + 0x9E3779B97F4A7C15ull))) {}
  // The whole state, for checkpoints: a generator set to a saved state continues the same sequence.
  std::uint64_t state() const { return s_; }
  void set_state(std::uint64_t s) { s_ = s; }
  std::uint64_t next() { return mix(s_ += 0x9E3779B97F4A7C15ull); }
  double uniform() { return (next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  double normal() {  // Box-Muller, one value per call
    double u1;
    do u1 = uniform();
    while (u1 <= 0);
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * uniform());
  }

 private:
  static std::uint64_t mix(std::uint64_t z) {  // splitmix64 finaliser
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint64_t s_;
};

}  // namespace grainlab
