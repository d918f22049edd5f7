#pragma once
// Validation suites by name. `grainlab validate` runs the ones asked for (all by default).
#include <functional>
#include <string>
#include <vector>

#include "engine.hpp"
#include "report.hpp"

namespace grainlab::validation {

struct SuiteOptions {
  bool quick = false;                                                 // smaller versions for CI
  std::function<void(const std::string&)> log;                        // progress lines
  std::function<void(std::size_t done, std::size_t total)> progress;  // runs of an ensemble
  std::string out_dir;  // the report folder: suites may write example run files there (rank 0)
  // impacts-3d (full): the sand gun's checkpoint file (empty: none), so its hours are spent once
  std::string sand_gun_checkpoint;
  // A folder where suites keep their long ensembles as they go (ensemble_checkpoint.hpp; empty: none).
  // `validate` gives OUT/.parts/ensembles-..., named by the quick flag and the binary, so that a suite
  // stopped part-way and continued with --resume takes the runs it had finished.
  std::string ensembles_dir;
  // That folder's file for the ensemble `name` (empty without a folder).
  std::string ensemble_checkpoint(const std::string& name) const {
    return ensembles_dir.empty() ? std::string() : ensembles_dir + "/" + name + ".ck.h5";
  }
};

struct Suite {
  std::string name, description;
  std::function<void(Report&, const SuiteOptions&)> run;
  // Typical wall time of the quick form on one core, minutes (measured two suites at a time on 2 cores,
  // 2026-12-04). Orders the processes of `validate --jobs` (the longest start first, so the last to
  // finish is a short one) and weighs each suite in its progress bar's estimate of the time left.
  double quick_minutes = 0.5;
};

// run_ensemble for a suite: with an ensembles folder, its runs are kept there under `name` as they end, so
// that a suite continued by `validate --resume` takes up the runs it had finished. `name` must tell the
// ensemble from every other of the same mode (the folder is the binary's and the mode's): engine, case,
// parameters; not the number of runs, which decides nothing about run i.
std::vector<std::vector<double>> suite_ensemble(const SuiteOptions& o, const std::string& name,
                                                std::size_t runs, std::size_t width,
                                                const std::function<std::vector<double>(std::size_t)>& run);

const std::vector<Suite>& suites();
const Suite* find_suite(const std::string& name);

void run_thesis_code_suite(Report& r, const SuiteOptions& o);
void run_single_body_suite(Report& r, const SuiteOptions& o);
void run_loaded_die_suite(Report& r, const SuiteOptions& o);
void run_loaded_die_3d(Report& r, const SuiteOptions& o);
void run_tumbling_polygon_suite(Report& r, const SuiteOptions& o);
void run_block_incline_suite(Report& r, const SuiteOptions& o);
void run_pair_impact_suite(Report& r, const SuiteOptions& o);
void run_stability_suite(Report& r, const SuiteOptions& o);
void run_impacts_suite(Report& r, const SuiteOptions& o);  // the 3-D part of the suite
void run_impacts_3d_suite(Report& r, const SuiteOptions& o);
void run_saltation_suite(Report& r, const SuiteOptions& o);
void run_ripples_suite(Report& r, const SuiteOptions& o);
void run_dem_saltation_suite(Report& r, const SuiteOptions& o);
void run_hybrid_suite(Report& r, const SuiteOptions& o);
// The 3-D single-body checks on one engine; appends a row to the markdown table `md`.
void single_body_3d_checks(Report& r, const std::string& engine, std::string& md);
// g in cm/s^2, as the thesis and the analytic references use it.
inline constexpr double kG = 981.0;

// Builds a scene from TOML text on an engine (the suites' scenes are written inline).
std::unique_ptr<Engine> engine_for(const std::string& engine, const std::string& toml,
                                   const std::vector<std::string>& sets = {});
// A r = 1 cm disc (2-D) or sphere (3-D), density 2, k_n = 5e6, 0.05 cm above a wall and moving onto it at
// `speed`; `material_line` is the normal-damping line of its material (e.g. "restitution = 0.7" or
// "damping_n = 1000.0").
std::string bounce_scene(int dimension, double speed, const std::string& material_line);
// Outgoing / incoming speed of that body's first bounce on `engine`.
double bounce_restitution(const std::string& engine, double speed, const std::string& material_line,
                          int dimension = 2);

}  // namespace grainlab::validation
