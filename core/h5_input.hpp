#pragma once
// Reading back a run file (grainlab run's HDF5) with every part checked, so a truncated or corrupt file
// is reported as such instead of half-read.
#include <map>
#include <string>

namespace grainlab {

struct RunFileSummary {
  std::map<std::string, std::string> text;  // root string attributes (version, engine, units, ...)
  std::size_t frames = 0, bodies = 0;
  double first_time = 0, last_time = 0;
  std::map<std::string, double> diagnostics;
};

// Opens `path` and reads every frame's datasets and the energy table, checking their shapes against
// each other. Throws InputError (key "file") naming what is missing, unreadable or inconsistent.
RunFileSummary read_run_file(const std::string& path);

}  // namespace grainlab
