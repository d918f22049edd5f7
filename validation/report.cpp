#include "report.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "h5_output.hpp"
#include "plot_script.hpp"

namespace grainlab::validation {

namespace fs = std::filesystem;

void Report::append(Report&& part) {
  for (auto& c : part.checks) checks.push_back(std::move(c));
  for (auto& m : part.markdown) markdown.push_back(std::move(m));
  for (auto& p : part.plots) plots.push_back(std::move(p));
  for (auto& t : part.samples) samples.push_back(std::move(t));
  for (auto& t : part.times) times.push_back(std::move(t));
}

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
  if (!r.times.empty()) {
    md += "## Time per suite\n\n| suite | wall time (s) |\n|---|---|\n";
    for (const SuiteTime& t : r.times) md += fmt::format("| {} | {:.1f} |\n", t.suite, t.seconds);
  }
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

nlohmann::json exact_list(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(exact_json(x));
  return a;
}
std::vector<double> from_exact_list(const nlohmann::json& j) {
  std::vector<double> v;
  for (const auto& x : j) v.push_back(from_exact_json(x));
  return v;
}

}  // namespace

nlohmann::json exact_json(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

double from_exact_json(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "nan") return NAN;
  if (s == "inf" || s == "-inf") return s[0] == '-' ? -INFINITY : INFINITY;
  throw std::runtime_error("not a number: " + s);
}

std::string report_part_json(const Report& r) {
  nlohmann::json j;
  j["schema"] = "grainlab-report-part/1";
  for (const Check& c : r.checks)
    j["checks"].push_back({{"id", c.id},
                           {"engine", c.engine},
                           {"value", exact_json(c.value)},
                           {"reference", exact_json(c.reference)},
                           {"tolerance", exact_json(c.tolerance)},
                           {"passed", c.passed},
                           {"note", c.note},
                           {"limitation", c.limitation}});
  j["markdown"] = r.markdown;
  for (const PlotSpec& p : r.plots) {
    nlohmann::json series = nlohmann::json::array();
    for (const auto& s : p.series)
      series.push_back({{"label", s.label},
                        {"style", s.style},
                        {"x", exact_list(s.x)},
                        {"y", exact_list(s.y)},
                        {"err", exact_list(s.err)}});
    j["plots"].push_back({{"file", p.file},
                          {"title", p.title},
                          {"xlabel", p.xlabel},
                          {"ylabel", p.ylabel},
                          {"logx", p.logx},
                          {"logy", p.logy},
                          {"series", series}});
  }
  for (const SampleTable& t : r.samples) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& row : t.rows) rows.push_back(exact_list(row));
    j["samples"].push_back(
        {{"name", t.name}, {"description", t.description}, {"columns", t.columns}, {"rows", rows}});
  }
  for (const SuiteTime& t : r.times) j["times"].push_back({{"suite", t.suite}, {"seconds", t.seconds}});
  return j.dump() + "\n";
}

Report read_report_part(const std::string& text) {
  Report r;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.value("schema", "") != "grainlab-report-part/1")
      throw std::runtime_error("not a grainlab-report-part/1 file");
    const nlohmann::json none = nlohmann::json::array();
    for (const auto& c : j.value("checks", none)) {
      Check k;
      k.id = c.at("id"), k.engine = c.at("engine"), k.note = c.at("note"), k.limitation = c.at("limitation");
      k.value = from_exact_json(c.at("value")), k.reference = from_exact_json(c.at("reference"));
      k.tolerance = from_exact_json(c.at("tolerance")), k.passed = c.at("passed");
      r.checks.push_back(std::move(k));
    }
    for (const auto& m : j.value("markdown", none)) r.markdown.push_back(m.get<std::string>());
    for (const auto& p : j.value("plots", none)) {
      PlotSpec s;
      s.file = p.at("file"), s.title = p.at("title"), s.xlabel = p.at("xlabel"), s.ylabel = p.at("ylabel");
      s.logx = p.at("logx"), s.logy = p.at("logy");
      for (const auto& q : p.at("series"))
        s.series.push_back({q.at("label"), q.at("style"), from_exact_list(q.at("x")),
                            from_exact_list(q.at("y")), from_exact_list(q.at("err"))});
      r.plots.push_back(std::move(s));
    }
    for (const auto& t : j.value("samples", none)) {
      SampleTable s{t.at("name"), t.at("description"), t.at("columns").get<std::vector<std::string>>(), {}};
      for (const auto& row : t.at("rows")) s.rows.push_back(from_exact_list(row));
      r.samples.push_back(std::move(s));
    }
    for (const auto& t : j.value("times", none)) r.times.push_back({t.at("suite"), t.at("seconds")});
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(std::string("malformed report part: ") + e.what());
  }
  return r;
}

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
  if (plots.empty() || !missing_for_plots("plot_report.py").empty()) return;
  if (const std::string why = run_plot_script("plot_report.py", {dir}); !why.empty())
    fmt::print(stderr, "warning: plotting failed: {}\n", why);
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
