#include "lattice_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <vector>

#include "bin_model.hpp"
#include "lattice_model.hpp"

namespace grainlab::bench {

namespace {

// Median over `repeats` of events per second; `make` builds a fresh state (untimed), `run` is timed.
double median_rate(int repeats, double events, const std::function<std::function<void()>()>& make) {
  std::vector<double> rates;
  for (int k = 0; k < repeats; ++k) {
    const std::function<void()> run = make();
    const auto t0 = std::chrono::steady_clock::now();
    run();
    rates.push_back(events / std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(rates.begin(), rates.end());
  return rates[rates.size() / 2];
}

}  // namespace

int run_lattice_bench(const LatticeBenchOptions& o) {
  using ripples::LatticeModel;
  using ripples::LatticeParams;
  LatticeParams p;  // the combined run of Fig. 5.22: forward 15, backward 5, half brink ejection
  p.columns = o.columns;
  const long timed = std::lround(o.timed * o.columns / 2), warm = std::lround(o.warmup * o.columns / 2);
  auto lattice = [&](long warmup) {
    return [&, warmup]() -> std::function<void()> {
      auto m = std::make_shared<LatticeModel>(p);
      m->fire(warmup);
      return [m, timed] { m->fire(timed); };
    };
  };
  const double young = median_rate(o.repeats, double(timed), lattice(0));
  const double developed = median_rate(o.repeats, double(timed), lattice(warm));
  ripples::BinModelParams b;
  b.bins = o.columns;
  const double bins = median_rate(o.repeats, double(timed), [&]() -> std::function<void()> {
    auto m = std::make_shared<ripples::BinModel>(b);
    return [m, timed] { m->fire(timed); };
  });
  fmt::print(
      "lattice-bed model, {} columns, {} impacts timed, median of {}: {:.3g} impacts/s on a flat start, "
      "{:.3g} impacts/s on ripples after {} ejections per surface grain; Haff's bin model ({} bins, same "
      "shots): {:.3g} shots/s (lattice / bin: {:.2f})\n",
      o.columns, timed, o.repeats, young, developed, o.warmup, o.columns, bins, developed / bins);
  if (!o.json.empty()) {
    std::ofstream(o.json) << nlohmann::json{{"columns", o.columns},
                                            {"impacts_timed", timed},
                                            {"repeats", o.repeats},
                                            {"impacts_per_second_flat", young},
                                            {"impacts_per_second_developed", developed},
                                            {"bin_model_shots_per_second", bins}}
                                 .dump(2)
                          << "\n";
  }
  return 0;
}

}  // namespace grainlab::bench
