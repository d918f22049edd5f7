#pragma once
// `grainlab bench impact`: the cost of one Ch. III impact (384-disc bed, followed 0.07 s) on one core, as
// the median of repeated runs, beside the impulse engines on the same impact in the same sitting.
#include <string>
#include <vector>

namespace grainlab::bench {

struct ImpactBenchOptions {
  std::string case_name = "A";
  int repeats = 5;
  std::vector<std::string> peers = {"ode", "bullet"};  // measured once each on the same impact
  std::string json;
};

int run_impact_bench(const ImpactBenchOptions& o);

}  // namespace grainlab::bench
