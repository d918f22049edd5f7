#pragma once
// CLI11's range checks compare, and every comparison with NaN is false: `--ustar nan` passed a check of
// (0, 1000) and reached the model, which failed far from the option or ran on nonsense. No number on
// grainlab's command line may be NaN or infinite, so every numeric option given is checked for that once,
// after parsing, with the option's name in the message (exit 2, before any work).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <string>

#include "input_error.hpp"

namespace grainlab::cli {

// Whether `text` reads whole as a floating-point number that is not finite ("nan", "-inf", "Infinity"...).
inline bool non_finite_number(const std::string& text) {
  if (text.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && !std::isfinite(v);
}

// Throws InputError for the first numeric option (CLI11 type FLOAT, or a list of them) of `app` or of its
// parsed subcommands that was given a NaN or an infinity.
inline void refuse_non_finite_numbers(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->count() == 0 || opt->get_type_name().find("FLOAT") == std::string::npos) continue;
    for (const std::string& value : opt->results())
      if (non_finite_number(value)) throw InputError({opt->get_name(), 0}, value, "must be a finite number");
  }
  for (const CLI::App* sub : app.get_subcommands()) refuse_non_finite_numbers(*sub);
}

}  // namespace grainlab::cli
