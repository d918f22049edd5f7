#pragma once
// `grainlab bench hybrid`: airborne grain-steps per second of the 3-D hybrid model (issue #17) on one core,
// in a saturated flux run over a flat bed (drag, collisions, splash and wind updates all included), as the
// median of repeated runs, beside the same run without mid-air collisions measured in the same sitting.
#include <string>

namespace grainlab::bench {

struct HybridBenchOptions {
  double length = 400, width = 10;  // grain diameters
  double u_star = 40;               // cm/s
  double duration = 1000;           // t*; the first tenth is the transient from the trigger grains
  int repeats = 3;
  std::string json;
};

int run_hybrid_bench(const HybridBenchOptions& o);

}  // namespace grainlab::bench
