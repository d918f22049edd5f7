#pragma once
// Validation suites by name. `grainlab validate` runs the ones asked for (all by default).
#include <functional>
#include <string>
#include <vector>

#include "report.hpp"

namespace grainlab::validation {

struct SuiteOptions {
  bool quick = false;                           // smaller versions for CI
  std::function<void(const std::string&)> log;  // progress lines
};

struct Suite {
  std::string name, description;
  std::function<void(Report&, const SuiteOptions&)> run;
};

const std::vector<Suite>& suites();
const Suite* find_suite(const std::string& name);

void run_thesis_code_suite(Report& r, const SuiteOptions& o);
void run_single_body_suite(Report& r, const SuiteOptions& o);
// The 3-D single-body checks on one engine; appends a row to the markdown table `md`.
void single_body_3d_checks(Report& r, const std::string& engine, std::string& md);
// Outgoing / incoming speed of a r = 1 cm disc's first bounce on a line on `engine`; `material_line` is
// the normal-damping line of its material (e.g. "restitution = 0.7" or "damping_n = 1000.0").
double bounce_restitution(const std::string& engine, double speed, const std::string& material_line);

}  // namespace grainlab::validation
