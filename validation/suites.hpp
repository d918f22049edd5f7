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

}  // namespace grainlab::validation
