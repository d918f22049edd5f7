#pragma once
// An option that changes nothing in the run asked for (a 3-D bed's option in a 2-D run, a CSV's --frame)
// is refused by name rather than silently ignored: the user meant something by it.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <string>

#include "input_error.hpp"

namespace grainlab::cli {

// What was given, as the message shows it: the values, or "given" for a flag.
inline std::string given_value(const CLI::Option* o) {
  return o->get_expected_max() == 0 ? "given" : fmt::format("{}", fmt::join(o->results(), " "));
}

// Throws naming `o` and `why` if `o` was given.
inline void refuse_if_given(const CLI::Option* o, const std::string& why) {
  if (o && o->count() > 0) throw InputError({o->get_name(), 0}, given_value(o), why);
}

}  // namespace grainlab::cli
