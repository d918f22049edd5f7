// Google Benchmark: the cost of the friction effect (the same settled bed with and without the
// friction effect; the frictionless kernel stores no shear history and does no tangential work), and the
// lattice-bed ripple model's impacts (issue #16's 10-million-per-second target) on a flat and a rippled bed,
// the per-step turn of a spinning sphere's orientation at a resting bed's spin and at an impact's, and
// the 3-D hybrid model's mid-air collision pass on a dilute saltation layer.
#include <benchmark/benchmark.h>

#include <random>

#include "airborne.hpp"
#include "bed_benchmark.hpp"
#include "lattice_model.hpp"
#include "scene.hpp"
#include "world.hpp"
#include "world3d_detail.hpp"

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

// 10,000 spheres' orientations turned one step (dt = 1e-6 s) at spins of about range(0) / 1000 rad/s:
// 3 is a resting bed's (h^2 ~ 1e-18: the series is skipped), 30,000 an impact's.
void BM_Turn(benchmark::State& state) {
  constexpr int n = 10000;
  std::vector<Quat> q(n, Quat::Identity());
  std::vector<Vec3> w(n);
  const double scale = static_cast<double>(state.range(0)) / 1000;
  for (int i = 0; i < n; ++i) w[i] = Vec3(1 + i % 7, 1 + i % 5, 1 + i % 3).normalized() * scale;
  for (auto _ : state)
    for (int i = 0; i < n; ++i) q[i] = dem::detail3d::turned(q[i], w[i], 1e-6);
  benchmark::DoNotOptimize(q.data());
  state.counters["turns_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
}

// The hybrid model's collision pass over range(2) grains on a bed of range(0) x range(1) diameters
// (d = 1), spread as a saltation layer: uniform over the bed, heights exponential with a mean of 5 d,
// moving downwind. 400 x 10 with 165 grains is `grainlab bench hybrid`'s flux run at u* = 40 cm/s;
// 2000 x 100 with 9,000 a wide ripple run's. Few pairs touch: what is timed is finding that out.
void BM_HybridCollisions(benchmark::State& state) {
  const double length = static_cast<double>(state.range(0)), width = static_cast<double>(state.range(1));
  const auto n = static_cast<std::size_t>(state.range(2));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> along(0, length), across(0, width), jitter(-1, 1);
  std::exponential_distribution<double> height(1.0 / 5);
  ripples::hybrid::Grains g;
  for (std::size_t i = 0; i < n; ++i)
    g.add(along(rng), across(rng), 0.5 + height(rng), 20 + 5 * jitter(rng), jitter(rng), 5 * jitter(rng), 0,
          i);
  ripples::hybrid::CollisionGrid grid(length, width, 1.0);
  grid.set_blocks(8);
  const ripples::hybrid::CollisionLaw law;
  for (auto _ : state) benchmark::DoNotOptimize(grid.collide_all(g, 1.0, law));
  state.counters["grains_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_HybridCollisions)
    ->Args({400, 10, 165})
    ->Args({2000, 100, 9000})
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_Turn)
    ->Arg(3)
    ->Arg(30000)
    ->Unit(benchmark::kMicrosecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);
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
