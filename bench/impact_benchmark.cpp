#include "impact_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "impacts.hpp"

namespace grainlab::bench {

using namespace grainlab::validation;

int run_impact_bench(const ImpactBenchOptions& o) {
  const ImpactCase& c = impact_case(o.case_name);
  BedSpec spec;
  spec.preparation = c.bed;
  const Bed bed = build_bed(spec);
  ImpactOptions io;
  std::vector<double> seconds;
  ImpactResult last;
  for (int k = 0; k < o.repeats; ++k) {
    // The same impact every time (run 0), so the repeats differ only by the machine's noise.
    last = run_impact(bed, c, 1, 0, io);
    seconds.push_back(last.wall_seconds);
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2];
  const double particles = static_cast<double>(bed.scene.bodies.size() + 1);
  nlohmann::json j{{"case", c.name},
                   {"particles", particles},
                   {"steps", last.steps},
                   {"repeats", o.repeats},
                   {"median_seconds", median},
                   {"min_seconds", seconds.front()},
                   {"max_seconds", seconds.back()},
                   {"particle_steps_per_second", particles * last.steps / median}};
  fmt::print(
      "impact CASE {}: {} discs followed 0.07 s, {:.0f} Verlet steps; median {:.3f} s over {} runs "
      "(min {:.3f}, max {:.3f}); {:.3g} particle-steps/s\n",
      c.name, particles, last.steps, median, o.repeats, seconds.front(), seconds.back(),
      particles * last.steps / median);
  for (const std::string& peer : o.peers) {
    ImpactOptions po = io;
    po.engine = peer;
    const ImpactResult r = run_impact(bed, c, 1, 0, po);
    j["peers"][peer] = {
        {"seconds", r.wall_seconds}, {"steps", r.steps}, {"ratio_to_native", r.wall_seconds / median}};
    fmt::print("  {} on the same impact (dt 1e-5 s, {:.0f} steps): {:.3f} s, {:.1f} x native\n", peer,
               r.steps, r.wall_seconds, r.wall_seconds / median);
  }
  if (!o.json.empty()) std::ofstream(o.json) << j.dump(2) << "\n";
  return 0;
}

}  // namespace grainlab::bench
