#pragma once
// Range checks for numeric options whose messages read as grainlab's other input errors. CLI11's own
// (CLI::Range, CLI::PositiveNumber) print their bounds with std::to_string: `--viscosity 0` was "Value 0
// not in range 0.000000 to 1000000.000000" and a positive number's upper bound took 300 digits. These print
// "--viscosity: 0: must lie in [1e-09, 1e+06]" and "must be > 0".
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <string>
#include <type_traits>

namespace grainlab::cli {

// A bound as people write it: 1e+06, not 1000000.000000.
template <typename T>
std::string bound_text(T bound) {
  if constexpr (std::is_integral_v<T>)
    return fmt::format("{}", bound);
  else
    return fmt::format("{:g}", bound);
}

// Inclusive [lo, hi]; T (deduced from the bounds) is the type the value is read as.
template <typename T>
CLI::Validator in_range(T lo, T hi) {
  return CLI::Validator(
      [lo, hi](std::string& input) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(input, value)) return fmt::format("{}: not a number", input);
        if (value < lo || value > hi)
          return fmt::format("{}: must lie in [{}, {}]", input, bound_text(lo), bound_text(hi));
        return {};
      },
      fmt::format("{} in [{}, {}]", CLI::detail::type_name<T>(), bound_text(lo), bound_text(hi)));
}

// Strictly positive (`strict`), or at least zero; no upper bound.
inline CLI::Validator sign_check(bool strict) {
  return CLI::Validator(
      [strict](std::string& input) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(input, value)) return fmt::format("{}: not a number", input);
        if (strict ? value > 0 : value >= 0) return {};
        return fmt::format("{}: must be {} 0", input, strict ? ">" : ">=");
      },
      strict ? "POSITIVE" : "NONNEGATIVE");
}
inline CLI::Validator positive() {
  return sign_check(true);
}
inline CLI::Validator non_negative() {
  return sign_check(false);
}

}  // namespace grainlab::cli
