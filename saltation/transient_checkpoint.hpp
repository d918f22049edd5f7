#pragma once
// A time-dependent saltation run's state (transient.hpp) in an HDF5 file with checksums, so that a long run
// can be stopped and continued to the same result. The file carries the options it was written under; a
// file from other options, another kind of file or a damaged one is refused with InputError naming it.
#include <string>

#include "transient.hpp"

namespace grainlab::saltation {

// `options`: a text that fixes everything the run computes (the command's fingerprint of its options).
void write_transient_checkpoint(const std::string& path, const TransientState& s, const std::string& options);
// Reads a state for options `o` (its grids size the state); throws InputError naming the file.
TransientState read_transient_checkpoint(const std::string& path, const TransientOptions& o,
                                         const std::string& options);

}  // namespace grainlab::saltation
