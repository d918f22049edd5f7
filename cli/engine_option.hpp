#pragma once
// `--engine NAME`, shared by the commands that simulate on a chosen engine (run, impact, splash). The name
// is checked when the command line is read, so a misspelt engine is reported before a bed is poured.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <string>
#include <vector>

#include "engine.hpp"

namespace grainlab::cli {

inline CLI::Option* add_engine_option(CLI::App* cmd, std::string& engine, const std::string& what) {
  const std::vector<std::string> names = engine_names();
  const std::string list = fmt::format("{}", fmt::join(names, ", "));
  CLI::Validator known(
      [names, list](std::string& name) -> std::string {
        if (std::find(names.begin(), names.end(), name) != names.end()) return {};
        return fmt::format("unknown engine \"{}\"; available: {}", name, list);
      },
      "ENGINE");
  return cmd->add_option("--engine", engine, fmt::format("{}: {}", what, list))
      ->default_val("native")
      ->check(known);
}

}  // namespace grainlab::cli
