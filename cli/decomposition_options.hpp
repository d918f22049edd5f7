#pragma once
// `--balance-every` and `--ranks-y`, shared by the commands that split a DEM domain over MPI ranks
// (`run`, `bench bed`): how often the ranks' regions are re-cut by load, and the grid of ranks.
#include <CLI/CLI.hpp>
#include <cstdint>

#include "domain.hpp"
#include "number_ranges.hpp"

namespace grainlab::cli {

inline void add_decomposition_options(CLI::App* cmd, std::uint64_t& balance_every, int& ranks_y) {
  cmd->add_option("--balance-every", balance_every,
                  "under mpirun: re-split the ranks' regions by load every N steps (0: never)")
      ->default_val(dem::kBalanceEveryDefault);
  cmd->add_option("--ranks-y", ranks_y,
                  "under mpirun: rows of the grid of ranks (1: slabs along x; must divide the ranks)")
      ->default_val(1)
      ->check(cli::positive());
}

}  // namespace grainlab::cli
