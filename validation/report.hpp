#pragma once
// A validation report: checks with their measured value, reference and tolerance, prose sections,
// plot data and plots. Written as report.json (machine-readable), report.md (for people) and PNGs.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "h5_output.hpp"

namespace grainlab::validation {

struct Check {
  std::string id, engine;
  double value = 0, reference = 0, tolerance = 0;
  bool passed = false;
  std::string note;
  // A third-party engine's known shortcoming, with the measurement that shows it. A failing check that
  // carries one is reported as a documented limitation and does not fail the report. The native engine
  // cannot carry one: it must pass every check.
  std::string limitation;
  bool counts_as_failure() const { return !passed && (limitation.empty() || engine.rfind("native", 0) == 0); }
  // Marks the check with a limitation (see above); returns it for chaining.
  Check& known_limitation(std::string why) {
    limitation = std::move(why);
    return *this;
  }
};

// A table of numbers a plot script turns into a PNG (tools/plot_report.py).
struct PlotSpec {
  std::string file;  // PNG name inside the report folder
  std::string title, xlabel, ylabel;
  bool logx = false;
  struct Series {
    std::string label, style;  // style: "line", "points", "dashed", "linepoints"
    std::vector<double> x, y;
    std::vector<double> err;  // optional: half-width of each point's interval (drawn as error bars)
  };
  std::vector<Series> series;
  bool logy = false;  // last, so the many {file, ..., logx, series} initialisers stay valid
};

// How long one suite took (wall clock), for the report's timing table and for scheduling.
struct SuiteTime {
  std::string suite;
  double seconds = 0;
};

struct Report {
  std::vector<Check> checks;
  std::vector<std::string> markdown;  // sections, in order
  std::vector<PlotSpec> plots;
  std::vector<SampleTable> samples;  // raw per-run samples, written to results.h5 so any plot can be redone
  std::vector<SuiteTime> times;      // per suite, in the order they were added
  bool passed() const;
  // Appends everything `part` holds (checks, sections, plots, samples, times) after what is here.
  void append(Report&& part);
  // Adds a check: passed when |value - reference| <= tolerance (absolute).
  Check& expect_near(std::string id, std::string engine, double value, double reference, double tolerance,
                     std::string note);
  // Adds a check: passed when value <= limit.
  Check& expect_below(std::string id, std::string engine, double value, double limit, std::string note);
};

// The head of a markdown table: the given columns, then one per engine, and the separator row.
std::string markdown_table_head(const std::vector<std::string>& columns,
                                const std::vector<std::string>& engines);

// Writes plots.json into `dir` and draws the PNGs from it (tools/plot_report.py, if python3 is there).
void write_plots(const std::vector<PlotSpec>& plots, const std::string& dir);

// The whole report as JSON (every field, numbers exact), for `validate --jobs`: each suite runs in its own
// process and hands its part to the parent this way. read_report_part throws std::runtime_error naming
// what is missing or malformed.
std::string report_part_json(const Report& r);
Report read_report_part(const std::string& text);

// A number as JSON that reads back bit for bit: NaN and infinity as the strings "nan", "inf" and "-inf"
// (JSON has neither); and back (std::runtime_error for any other string). For files grainlab reads again
// (report parts, the cost study's checkpoint).
nlohmann::json exact_json(double v);
double from_exact_json(const nlohmann::json& j);

// Writes report.json, report.md, results.h5 (when there are samples) and the plots into `dir` (created if
// needed).
void write_report(const Report& r, const std::string& dir);

}  // namespace grainlab::validation
