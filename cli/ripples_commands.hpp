#pragma once
// `grainlab ripples ...`: the thesis's ripple models (Ch. V: worms, triangles, continuum, bins, lattice), the
// analysis of any surface, and the 3-D hybrid model of Huo et al. 2021 (hybrid, hybrid-flux, hybrid-focal).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "flux_model.hpp"
#include "ripple_config.hpp"

namespace grainlab::cli {

struct RipplesCommands {
  int links = 10, start = 5, steps = 416, worms = 200, length = 2, ring_steps = 200000;
  double A = 0.6, ratio = 0.6, beta = 5, alpha = 10;
  std::string law = "target";
  std::size_t runs = 20000;
  std::uint64_t seed = 1;
  bool json = false;
  int bins = 600;
  long shots = 2000000;
  std::string config, out;
  bool force = false;
  CLI::App *group = nullptr, *chain = nullptr, *ring = nullptr, *triangles = nullptr, *bin_cmd = nullptr,
           *wavelength = nullptr, *lattice = nullptr;
  int lattice_seeds = 1;
  bool list_models = false;
  std::string analyze_file;
  int analyze_frame = -1, analyze_smooth = 0;
  double analyze_sigma = 1, analyze_relief = 0;
  CLI::App *analyze = nullptr, *run = nullptr, *continuum = nullptr;
  double shape_speed = 0.1;
  double lattice_ejections = 0;  // not given: the config's (a given value is > 0)
  CLI::App *hybrid_flux = nullptr, *hybrid_ripples = nullptr, *hybrid_focal = nullptr;
  std::vector<double> focal_ustars{26, 30, 40, 50, 60};  // ripples hybrid-focal
  std::vector<double> focal_band{300, 1000};             // d: the log layer's heights
  double focal_above = 1;                                // d: crossings below are ignored
  double duration_override = 0;        // ripples hybrid --duration (>= 1 when given): 0 keeps the config's
  std::vector<std::string> overrides;  // ripples hybrid --set KEY=VALUE
  std::string hybrid_checkpoint, hybrid_restart;
  double checkpoint_every = 10000, stop_at = 0;  // t*
  double impacts_from = -1;                      // ripples hybrid --impacts-from: t*; < 0 logs none
  ripples::hybrid::FluxOptions flux;
  bool quiet = false;
  void add(CLI::App& app);
  int dispatch() const;  // -1 if none of these ran

 private:
  void add_worms();
  void add_triangles();
  void add_bins();
  void add_lattice();
  void add_continuum();
  void add_run();
  void add_analyze();
  void add_wavelength();
  void add_hybrid_flux();
  void add_hybrid_focal();
  void add_hybrid();
  void add_flux_model_options(CLI::App* c);
};

// Stops with exit status 2 if `out` exists and --force was not given (nothing is overwritten by accident).
void refuse_existing_out(const std::string& out, bool force);
// Draws RUN_spacetime.png beside a surface model's run file RUN.h5 (tools/plot_ripples.py; a machine
// without matplotlib gets a note instead). An existing PNG is kept unless `force`.
void write_spacetime_plot(const std::string& h5, bool force, bool json);
int lattice_command(const RipplesCommands& a);
int analyze_command(const RipplesCommands& a);
int run_command(const RipplesCommands& a);
int continuum_command(const RipplesCommands& a);
int hybrid_flux_command(const RipplesCommands& a);
int hybrid_ripples_command(const RipplesCommands& a);
int hybrid_focal_command(const RipplesCommands& a);
// The flux run's options that cannot run together (exit status 2, naming the option).
void check_flux_options(const ripples::hybrid::FluxOptions& o);
// A flux run (`run`: `o` made ready to run) that writes its state to `checkpoint` (when given, rank 0,
// every checkpoint_every t* and at the end) and continues from `restart` (when given; exit status 2 if it
// was written with other options than `o`'s, --duration aside).
ripples::hybrid::FluxResult run_flux_checkpointed(ripples::hybrid::FluxOptions run,
                                                  const ripples::hybrid::FluxOptions& o,
                                                  const std::string& checkpoint, const std::string& restart);
// The lattice model's splash mode: hop lengths (grain diameters) from a grainlab-splash/1 file, thrown
// ballistically or, with splash_wind, flown through the Ch. IV wind (saltation::wind_blown_hops).
ripples::SplashHops splash_hops(const ripples::LatticeRun& run);

}  // namespace grainlab::cli
