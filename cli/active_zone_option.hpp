#pragma once
// `--active-zone D`, shared by the commands that shoot grains into a 3-D bed (impact, sand-gun, splash):
// only the bed grains within D bed-grain diameters of each impact point move, the rest are held in place
// (ImpactOptions::active_radius; docs/impacts.md "An impact's active zone").
#include <CLI/CLI.hpp>
#include <string>

#include "number_ranges.hpp"

namespace grainlab::cli {

// `scope` says where the option applies ("--dimension 3, native: "), empty where it always does.
inline CLI::Option* add_active_zone_option(CLI::App* cmd, double& zone, const std::string& scope = {}) {
  return cmd
      ->add_option("--active-zone", zone,
                   scope +
                       "move only the bed grains within this many bed-grain diameters of each impact point "
                       "and hold the rest in place: an impact then costs what its neighbourhood costs "
                       "(docs/impacts.md \"An impact's active zone\" measures what it changes); 0: the whole "
                       "bed")
      ->default_val(0.0)
      ->check(cli::in_range(0.0, 1000.0));
}

}  // namespace grainlab::cli
