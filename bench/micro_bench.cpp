// Google Benchmark: the cost of the friction effect (the same settled bed with and without the
// friction effect; the frictionless kernel stores no shear history and does no tangential work), and the
// lattice-bed ripple model's impacts (issue #16's 10-million-per-second target) on a flat and a rippled bed.
#include <benchmark/benchmark.h>

#include "bed_benchmark.hpp"
#include "lattice_model.hpp"
#include "scene.hpp"
#include "world.hpp"

using namespace grainlab;

namespace {

// A bed with contacts, settled for 3000 steps.
dem::World settled_bed(bool friction) {
  bench::BedOptions o;
  o.nx = 60, o.ny = 40, o.frictionless = !friction;
  o.spacing = 2.0, o.first_row = 1.0;  // touching from the start: every step does contact work
  dem::World w(parse_scene(bench::bed_scene_toml(o), "<micro bed>"));
  for (int s = 0; s < 3000; ++s) w.step();
  return w;
}

void BM_BedStep(benchmark::State& state) {
  const bool friction = state.range(0) != 0;
  dem::World w = settled_bed(friction);
  for (auto _ : state) w.step();
  state.counters["particle_steps_per_s"] = benchmark::Counter(static_cast<double>(w.particles().size()),
                                                              benchmark::Counter::kIsIterationInvariantRate);
  state.counters["contacts"] = static_cast<double>(w.count_contacts());
  state.SetLabel(friction ? "friction" : "frictionless");
}

// The combined run of Fig. 5.22 on 10,000 columns, the same work as `grainlab bench lattice`: 20
// ejections per surface grain timed, after range(0) untimed ones (0: flat start; 100: developed ripples).
void BM_LatticeImpacts(benchmark::State& state) {
  ripples::LatticeParams p;
  p.columns = 10000;
  ripples::LatticeModel m(p);
  m.fire(state.range(0) * p.columns / 2);
  constexpr long kBatch = 10000;
  for (auto _ : state) m.fire(kBatch);
  state.counters["impacts_per_s"] = benchmark::Counter(kBatch, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(state.range(0) ? "rippled" : "flat");
}

}  // namespace

BENCHMARK(BM_LatticeImpacts)
    ->Arg(0)
    ->Arg(100)
    ->Iterations(10)
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_BedStep)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK_MAIN();
