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

// Which ends of a range belong to it: [lo, hi], (lo, hi], [lo, hi) or (lo, hi).
enum class Ends { closed, open_low, open_high, open };

// lo to hi, inclusive unless `ends` says otherwise; T (deduced from the bounds) is the type the value is
// read as. The help and the message show the range as written: "FLOAT in (0, 1000)".
template <typename T>
CLI::Validator in_range(T lo, T hi, Ends ends = Ends::closed) {
  const bool open_low = ends == Ends::open_low || ends == Ends::open;
  const bool open_high = ends == Ends::open_high || ends == Ends::open;
  const std::string range =
      fmt::format("{}{}, {}{}", open_low ? "(" : "[", bound_text(lo), bound_text(hi), open_high ? ")" : "]");
  return CLI::Validator(
      [lo, hi, open_low, open_high, range](std::string& input) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(input, value)) return fmt::format("{}: not a number", input);
        const bool below = open_low ? !(value > lo) : !(value >= lo);
        const bool above = open_high ? !(value < hi) : !(value <= hi);
        if (below || above) return fmt::format("{}: must lie in {}", input, range);
        return {};
      },
      fmt::format("{} in {}", CLI::detail::type_name<T>(), range));
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
