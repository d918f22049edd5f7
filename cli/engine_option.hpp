#pragma once
// `--engine NAME` (and any option naming engines), shared by the commands that simulate on a chosen engine
// (run, impact, splash). The name is checked when the command line is read, so a misspelt engine is reported
// before a bed is poured.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <string>
#include <vector>

#include "engine.hpp"

namespace grainlab::cli {

// The check of an engine's name on the command line: one of engine_names().
inline CLI::Validator known_engine() {
  const std::vector<std::string> names = engine_names();
  const std::string list = fmt::format("{}", fmt::join(names, ", "));
  return CLI::Validator(
      [names, list](std::string& name) -> std::string {
        if (std::find(names.begin(), names.end(), name) != names.end()) return {};
        return fmt::format("unknown engine \"{}\"; available: {}", name, list);
      },
      "ENGINE");
}

inline CLI::Option* add_engine_option(CLI::App* cmd, std::string& engine, const std::string& what) {
  return cmd->add_option("--engine", engine, fmt::format("{}: {}", what, fmt::join(engine_names(), ", ")))
      ->default_val("native")
      ->check(known_engine());
}

}  // namespace grainlab::cli
