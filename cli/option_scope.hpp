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

// `--stop-at T` (T > 0 when given) needs a checkpoint to stop into and must come before the run's end
// (`end`, as the message shows it: "--duration 2", "t* = 4000"), or it stops nothing.
inline void check_stop_at(double stop_at, const std::string& checkpoint, double duration,
                          const std::string& end) {
  if (!(stop_at > 0)) return;
  if (checkpoint.empty())
    throw InputError({"--stop-at", 0}, fmt::format("{}", stop_at), "needs --checkpoint to stop into");
  if (!(stop_at < duration))
    throw InputError({"--stop-at", 0}, fmt::format("{}", stop_at),
                     fmt::format("must be before the end of the run ({})", end));
}

}  // namespace grainlab::cli
