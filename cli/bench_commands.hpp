#pragma once
// `grainlab bench bed|impact|bed3d|lattice|hybrid`: the speed figures the issues ask for, each measured
// beside a peer where one exists (bench/README.md). The work itself is in bench/.
#include <CLI/CLI.hpp>

#include "bed3d_benchmark.hpp"
#include "bed_benchmark.hpp"
#include "hybrid_benchmark.hpp"
#include "impact_benchmark.hpp"
#include "lattice_benchmark.hpp"

namespace grainlab::cli {

struct BenchCommands {
  bench::BedOptions bed;
  bench::ImpactBenchOptions impact;
  bench::Bed3dOptions bed3d;
  bench::LatticeBenchOptions lattice;
  bench::HybridBenchOptions hybrid;

  CLI::App *bed_cmd = nullptr, *impact_cmd = nullptr, *bed3d_cmd = nullptr, *lattice_cmd = nullptr,
           *hybrid_cmd = nullptr;
  void add(CLI::App& app);
  // Runs the benchmark asked for; -1 if none was.
  int dispatch();

 private:
  void add_bed(CLI::App* bench);
  void add_impact(CLI::App* bench);
  void add_bed3d(CLI::App* bench);
  void add_lattice(CLI::App* bench);
  void add_hybrid(CLI::App* bench);
};

}  // namespace grainlab::cli
