#pragma once
// `grainlab saltation ...`: the thesis's Ch. IV models (conveyor, wind, transient, heights), the study over
// planets and grain sizes, and DEM saltation under a wind.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "clean_wind_heights.hpp"
#include "dem_saltation.hpp"
#include "wind_model.hpp"

namespace grainlab::cli {

// CASE 7 of Table 4.5 is the sand gun's measured splash (Tables 3.11-3.12), on its sand 0.078 cm across.
constexpr int kSandGunCase = 7;
// What drives a run: the splash file, or the CASE.
std::string case_label(int splash_case, const std::string& file);
// The grains' diameter: CASE 7's sand unless --grain-diameter was given.
double case_grain_diameter(int splash_case, const CLI::Option* diameter_option, double diameter);
// A splash file if one is given, else the sand gun (CASE 7) or Table 4.3's CASE scaled by `scale`.
saltation::SplashKernel case_splash(int splash_case, const std::string& file,
                                    const saltation::WindModelOptions& o, double scale);

struct SaltationCommands {
  std::string case_name, order = "simultaneous";
  double F0 = 50, v_oy0 = 3;
  int max_iterations = 10000;
  bool json = false;
  // grainlab saltation wind
  int wind_case = 0;
  std::string splash_file;
  double grain_diameter = 0.025, reynolds_factor = 1, flux_damping = 0.5, drag_smoothing = 0, launch_min = 0,
         launch_dv = 5;
  std::string ejecta_below = "line";  // a moments-only splash file's ejecta below its slowest impacts
  double u_star = 35, tolerance = 0.01;
  double trajectory_tolerance = 1e-8, sample_interval = 5e-4;
  double start_below = 0;  // conveyor A-C: a narrow start (not given: flat)
  std::string planet;
  double gravity = 0, air_density = 0, viscosity = 0, grain_density_wind = 2.6;  // 0: the preset's
  int launch_bins = 80, vx_bins = 0, profile_flights = 16;
  double vx_min = -100;
  bool wind_json = false, force = false;
  std::string out;
  // grainlab saltation study
  int study_case = 1;
  std::vector<std::string> planets{"earth"};
  std::vector<double> diameters{0.0125, 0.025, 0.05}, ustar_factors{1.2, 1.5, 2, 3, 4};
  double grain_density = 2.6;
  std::string study_out, study_restart;
  int study_stop_after = 0;
  bool study_json = false, quiet = false;
  // grainlab saltation heights (Fig. 4.22)
  saltation::CleanWindSpec heights_spec;
  std::string heights_out;
  bool heights_json = false;
  // grainlab saltation transient (eq. 4.35)
  int transient_case = 1;
  double transient_ustar = 75, transient_dt = 0.005, transient_duration = 4, transient_record = 0.01;
  std::vector<double> transient_changes;  // time, u* pairs
  std::string transient_splash, transient_out, transient_checkpoint, transient_restart;
  double transient_checkpoint_every = 60, transient_stop_at = 0;
  bool transient_json = false;
  // grainlab saltation dem
  validation::DemSaltationOptions dem;
  std::string dem_out;
  bool dem_json = false;
  // given or not: CASE 7's grains default to the sand gun's
  CLI::Option *wind_diameter_option = nullptr, *transient_diameter_option = nullptr;
  // conveyor: the options of the map (D, E) and of the distribution splash (A-C), refused for the other
  std::vector<CLI::Option*> map_options, distribution_options;
  CLI::App *group = nullptr, *conveyor = nullptr, *wind = nullptr, *study = nullptr, *dem_app = nullptr,
           *heights = nullptr, *transient = nullptr;
  void add(CLI::App& app);
  int dispatch() const;  // -1 if none of these ran

 private:
  void add_conveyor();
  void add_wind();
  void add_study();
  void add_dem();
  void add_heights();
  void add_transient();
};

int study_command(const SaltationCommands& a);
int dem_command(const SaltationCommands& a);
int heights_command(const SaltationCommands& a);
int transient_command(const SaltationCommands& a);

}  // namespace grainlab::cli
