#pragma once
// Ripple models read TOML configs with the scenes' strict reader: unknown keys, wrong types and values out
// of range stop with the file, line and key, and exit status 2. docs/ripples.md lists the keys.
#include <string>

#include "bin_model.hpp"
#include "lattice_model.hpp"

namespace grainlab::ripples {

struct BinModelRun {
  BinModelParams params;
  long shots = 2000000;
  int frames = 100;  // surfaces recorded for h(x, t)
  std::string text;  // the config as read
};

// Reads `[bins]` from TOML text (`path` names it in errors). Throws InputError.
BinModelRun parse_bin_model_config(const std::string& text, const std::string& path);
BinModelRun read_bin_model_config(const std::string& path);

struct LatticeRun {
  LatticeParams params;
  double ejections_per_grain = 10;  // run length: impacts per surface grain
  int frames = 100;
  std::string text;
};
// Reads `[lattice]` (docs/ripples.md lists the keys). Throws InputError.
LatticeRun parse_lattice_config(const std::string& text, const std::string& path);
LatticeRun read_lattice_config(const std::string& path);

}  // namespace grainlab::ripples
