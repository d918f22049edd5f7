#include "report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"

#ifndef GRAINLAB_SOURCE_DIR
#define GRAINLAB_SOURCE_DIR "."
#endif

namespace grainlab::validation {

namespace fs = std::filesystem;

bool Report::passed() const {
  for (const Check& c : checks)
    if (c.counts_as_failure()) return false;
  return !checks.empty();
}

Check& Report::expect_near(std::string id, std::string engine, double value, double reference,
                           double tolerance, std::string note) {
  const bool ok = std::isfinite(value) && std::abs(value - reference) <= tolerance;
  checks.push_back({std::move(id), std::move(engine), value, reference, tolerance, ok, std::move(note), {}});
  return checks.back();
}

Check& Report::expect_below(std::string id, std::string engine, double value, double limit,
                            std::string note) {
  const bool ok = std::isfinite(value) && value <= limit;
  checks.push_back({std::move(id), std::move(engine), value, limit, limit, ok, std::move(note), {}});
  return checks.back();
}

namespace {

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

std::string to_json(const Report& r) {
  nlohmann::json j;
  j["passed"] = r.passed();
  j["checks"] = nlohmann::json::array();
  for (const Check& c : r.checks)
    j["checks"].push_back({{"id", c.id},
                           {"engine", c.engine},
                           {"value", finite_or_null(c.value)},
                           {"reference", finite_or_null(c.reference)},
                           {"tolerance", finite_or_null(c.tolerance)},
                           {"passed", c.passed},
                           {"limitation", c.passed ? std::string() : c.limitation},
                           {"note", c.note}});
  return j.dump(2) + "\n";
}

std::string to_markdown(const Report& r) {
  const auto failed =
      std::count_if(r.checks.begin(), r.checks.end(), [](auto& c) { return c.counts_as_failure(); });
  const auto limited = std::count_if(r.checks.begin(), r.checks.end(),
                                     [](auto& c) { return !c.passed && !c.counts_as_failure(); });
  std::string md = fmt::format(
      "# grainlab validation report\n\ngrainlab {}. Overall: **{}** ({} checks, {} failed, {} documented "
      "engine "
      "limitations).\n\n",
      GRAINLAB_VERSION, r.passed() ? "PASSED" : "FAILED", r.checks.size(), failed, limited);
  md += "| check | engine | value | reference | tolerance | result | note |\n|---|---|---|---|---|---|---|\n";
  for (const Check& c : r.checks)
    md += fmt::format("| {} | {} | {:.6g} | {:.6g} | {:.3g} | {} | {} |\n", c.id, c.engine, c.value,
                      c.reference, c.tolerance,
                      c.passed                ? "pass"
                      : c.counts_as_failure() ? "**FAIL**"
                                              : "limitation: " + c.limitation,
                      c.note);
  md += "\n";
  for (const std::string& s : r.markdown) md += s + "\n";
  return md;
}

std::string plots_json(const Report& r) {
  nlohmann::json j = nlohmann::json::array();
  for (const PlotSpec& p : r.plots) {
    nlohmann::json s = nlohmann::json::array();
    for (const auto& ser : p.series)
      s.push_back({{"label", ser.label}, {"style", ser.style}, {"x", ser.x}, {"y", ser.y}, {"err", ser.err}});
    j.push_back({{"file", p.file},
                 {"title", p.title},
                 {"xlabel", p.xlabel},
                 {"ylabel", p.ylabel},
                 {"logx", p.logx},
                 {"logy", p.logy},
                 {"series", s}});
  }
  return j.dump(1) + "\n";
}

}  // namespace

std::string markdown_table_head(const std::vector<std::string>& columns,
                                const std::vector<std::string>& engines) {
  std::string head = "|", rule = "|";
  for (const auto* list : {&columns, &engines})
    for (const std::string& c : *list) head += " " + c + " |", rule += "---|";
  return head + "\n" + rule + "\n";
}

void write_plots(const std::vector<PlotSpec>& plots, const std::string& dir) {
  fs::create_directories(dir);
  Report only_plots;
  only_plots.plots = plots;
  write_file_atomically((fs::path(dir) / "plots.json").string(), plots_json(only_plots));
  // Plots are drawn by Debian's matplotlib; a machine without it still gets the numbers.
  const std::string script = std::string(GRAINLAB_SOURCE_DIR) + "/tools/plot_report.py";
  if (!plots.empty() && fs::exists(script) && fs::exists("/usr/bin/python3")) {
    const std::string cmd = fmt::format("/usr/bin/python3 '{}' '{}' > /dev/null 2>&1", script, dir);
    if (std::system(cmd.c_str()) != 0) fmt::print(stderr, "warning: plotting failed (run: {})\n", cmd);
  }
}

void write_report(const Report& r, const std::string& dir) {
  fs::create_directories(dir);
  write_file_atomically((fs::path(dir) / "report.json").string(), to_json(r));
  write_file_atomically((fs::path(dir) / "report.md").string(), to_markdown(r));
  if (!r.samples.empty())
    write_sample_tables(
        (fs::path(dir) / "results.h5").string(), r.samples,
        {{"grainlab_version", GRAINLAB_VERSION}, {"contents", "raw samples of grainlab validate"}});
  write_plots(r.plots, dir);
}

}  // namespace grainlab::validation
