#pragma once
// The Ch. III commands: `grainlab bed` (build an impact bed), `grainlab impact` (impacts of one case of
// Table 3.1), `grainlab rebound-model` (Appendix III.1) and `grainlab splash` (the splash function as a
// grainlab-splash/1 file).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace grainlab::cli {

struct ImpactCommands {
  // grainlab bed
  std::string preparation = "loose", bed_out;
  std::uint64_t bed_seed = 1;
  bool periodic = false, unlevelled = false, bed_force = false, bed_json = false;
  double width = 67.3;
  int count = 384;
  // grainlab impact
  std::string case_name, engine = "native", record;
  std::vector<std::string> bed_files;
  std::size_t runs = 10, beds = 1;
  double steps_per_contact = 30;
  std::uint64_t seed = 1;
  bool impact_json = false, quiet = false, force = false;
  int dimension = 2, spheres = 2000;  // --dimension 3: spheres in the poured bed
  bool hold = false;                  // --dimension 3: report how far the bed moves alone
  bool settle_on_engine = false;      // --dimension 3: settle the bed on --engine before its impacts
  std::string grains = "sphere";      // --dimension 3: "sphere" or "polyhedron" (irregular grains)
  std::vector<double> box;            // --dimension 3: the box's x and y (cm); empty: 67.3 x 20
  std::string impact_checkpoint;      // the finished impacts (--dimension 3: and the bed's build)
  double active_zone = 0;             // --dimension 3: bed-grain diameters about the impact that move
  // grainlab rebound-model
  int model_case = 2;
  double alpha = 15, spin = 0, gap = 0, radius_ratio = 1;
  std::optional<double> mass_ratio, sigma;  // not given: the case's (Table 3.10)
  bool model_json = false;

  // grainlab splash
  std::string splash_out;
  bool splash_quick = false, sand_gun = false, splash_force = false, splash_json = false,
       splash_quiet = false;
  std::size_t splash_runs = 0, splash_beds = 0;
  std::uint64_t splash_seed = 1;
  std::string splash_engine = "native", splash_checkpoint, splash_restart;
  std::size_t splash_stop_after = 0;
  std::vector<double> splash_speeds, splash_angles;
  int splash_dimension = 2, splash_spheres = 2000;
  std::vector<double> splash_box;
  double splash_active_zone = 0;
  std::string splash_bed_checkpoint;

  CLI::App *bed_cmd = nullptr, *impact_cmd = nullptr, *rebound_cmd = nullptr, *splash_cmd = nullptr;
  void add(CLI::App& app);
  // Runs the command that was asked for; -1 if none of these was.
  int dispatch() const;

 private:
  void add_bed(CLI::App& app);
  void add_impact(CLI::App& app);
  void add_splash(CLI::App& app);
  void add_rebound_model(CLI::App& app);
};

}  // namespace grainlab::cli
