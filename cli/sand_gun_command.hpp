#pragma once
// `grainlab sand-gun`: the thesis's sand-gun experiment (Tables 3.11-3.12) with spheres of a sieved sand
// on the native 3-D engine (validation/sand_gun3d.hpp).
#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace grainlab::cli {

struct SandGunCommand {
  int spheres = 20000;
  std::vector<std::size_t> rows;
  std::size_t runs = 20;
  std::uint64_t seed = 1, bed_seed = 1;
  double stiffness = 1, visible_above = 1, active_zone = 0;
  std::string checkpoint, grains = "sphere", plots;
  bool json = false, quiet = false;

  CLI::App* cmd = nullptr;
  void add(CLI::App& app);
  // Runs the command if it was asked for; -1 if it was not.
  int dispatch() const;
};

}  // namespace grainlab::cli
