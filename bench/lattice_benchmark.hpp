#pragma once
// `grainlab bench lattice`: impacts per second of the lattice-bed ripple model (thesis Fig. 5.21) on one
// core, on a young surface and on developed ripples, as medians of repeated runs, beside Haff's bin model
// (shots per second) measured in the same sitting.
#include <string>

namespace grainlab::bench {

struct LatticeBenchOptions {
  int columns = 10000;
  double warmup = 100;  // ejections per surface grain before the "developed" timing (untimed)
  double timed = 20;    // ejections per surface grain timed
  int repeats = 5;
  std::string json;
};

int run_lattice_bench(const LatticeBenchOptions& o);

}  // namespace grainlab::bench
