#pragma once
// `grainlab inspect FILE`: read a file grainlab wrote back, every part checked, and say what it holds.
#include <string>

namespace grainlab::cli {

// A run file of `grainlab run` (every frame and the energy table), a grainlab-splash/1 file (the checked
// reader, then its grid), or a file of tables (the ripple, saltation and hybrid commands' outputs and
// checkpoints: each top-level table read against its columns). Throws InputError (exit status 2) for a
// file that is not HDF5, truncated or damaged.
int inspect_command(const std::string& path);

}  // namespace grainlab::cli
