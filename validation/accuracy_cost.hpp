#pragma once
// What accuracy costs in time (`grainlab cost`): for each scene, each engine's accuracy knobs are swept;
// every setting gets its error against a reference (analytic, or the finest native run) and its cost
// (median wall time of repeats, steps, rejected steps, solver iterations).
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "report.hpp"

namespace grainlab::validation {

// One accuracy setting of one engine: the --set overrides that make it.
struct CostSetting {
  std::string engine;  // native, box2d, ode, bullet
  std::string method;  // the curve it belongs to: "native verlet", "ode quick-step", ...
  std::string knob;    // what this curve varies: "dt", "tolerance", "k_n", "iterations", "substeps"
  double value = 0;
  std::vector<std::string> sets;
};

// What one run at one setting measured.
struct CostMeasurement {
  double value = 0;
  double half_width = 0;  // 95 % interval of a statistical value (0 otherwise)
  double steps = 0, rejected = 0, iterations = 0;
  std::vector<double> extra;  // further measured quantities of a scene (the bed: packing, coordination)
  std::string detail;         // how a scene reports them
};

struct CostScene {
  std::string name, description;
  std::string reference_note;  // how the reference was obtained
  bool statistical = false;    // a proportion from an ensemble: measured once, not repeated
  std::function<CostMeasurement(const CostSetting&)> measure;
  // The analytic value, or (statistical scenes) the finest native run with its interval.
  std::function<CostMeasurement()> reference;
  std::vector<CostSetting> settings;
  bool expensive = false;  // timed once, not repeated (a 1,000-grain pour)
  // Error of a measurement against the reference; empty: |value - reference| / |reference|.
  std::function<double(const CostMeasurement&, const CostMeasurement&)> error;
};

struct CostRow {
  std::string scene, engine, method, knob;
  double value = 0, measured = 0, error = 0, error_half_width = 0;  // error: relative, or absolute for p_h
  double seconds = 0, steps = 0, rejected = 0, iterations = 0;
  std::string failure = {};  // why the run stopped (then error is NaN): e.g. the adaptive step underflowed
  std::string detail = {};   // the scene's further quantities, as text
};

struct CostOptions {
  bool quick = false;
  int repeats = 3;
  std::vector<std::string> scenes;  // empty: all
  std::function<void(const std::string&)> log;
  // A scene's rows from an interrupted study (not measured again), or an empty optional.
  std::function<std::optional<std::vector<CostRow>>(const std::string& scene)> taken;
  // Called with each scene's rows as it is finished (to keep them for a resumed study).
  std::function<void(const std::string& scene, const std::vector<CostRow>& rows)> finished;
};

// A row as JSON. `exact`: NaN and infinity as strings, so the row reads back bit for bit (the study's
// checkpoint, read by cost_row_from_json, which throws std::runtime_error naming what is wrong); otherwise
// as null, for plain JSON readers (cost.json).
nlohmann::json cost_row_json(const CostRow& r, bool exact = false);
CostRow cost_row_from_json(const nlohmann::json& j);

// The scenes of the study (quick: fewer settings and throws).
std::vector<CostScene> cost_scenes(bool quick);
std::vector<CostRow> run_cost_study(const CostOptions& o);

// The cheapest row (least seconds) of one curve reaching `target` error, or nullptr ("not reached").
const CostRow* cheapest_reaching(const std::vector<CostRow>& rows, const std::string& scene,
                                 const std::string& method, double target);

// cost.json (one object per row) and cost.md (per scene: a Pareto plot of error against time, one curve
// per engine and method, and the cheapest setting reaching 1e-1, 1e-2, 1e-3), plus the plots.
void write_cost_report(const std::vector<CostRow>& rows, const std::vector<CostScene>& scenes,
                       const std::string& dir, bool quick);

}  // namespace grainlab::validation
