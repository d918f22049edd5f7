#pragma once
// `grainlab saltation ...`: the thesis's Ch. IV models (so far the conveyor-belt model).
#include <CLI/CLI.hpp>
#include <string>

namespace grainlab::cli {

struct SaltationCommands {
  std::string case_name, order = "simultaneous";
  double F0 = 50, v_oy0 = 3;
  int max_iterations = 10000;
  bool json = false;
  // grainlab saltation wind
  int wind_case = 0;
  std::string splash_file;
  double grain_diameter = 0.025, reynolds_factor = 1, flux_damping = 0.5;
  double u_star = 35, tolerance = 0.01;
  bool wind_json = false, force = false;
  std::string out;
  CLI::App *group = nullptr, *conveyor = nullptr, *wind = nullptr;
  void add(CLI::App& app);
  int dispatch() const;  // -1 if none of these ran
};

}  // namespace grainlab::cli
