#pragma once
// Reading back a run file (grainlab run's HDF5) with every part checked, so a truncated or corrupt file
// is reported as such instead of half-read.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "h5_handle.hpp"
#include "h5_output.hpp"

namespace grainlab {

// Opens `path` for reading, or throws InputError naming `key` if it is missing, a folder, not HDF5 or
// too damaged to open (every reader of grainlab's files starts here).
H5Handle open_hdf5_for_reading(const std::string& path, const std::string& key);

struct RunFileSummary {
  std::map<std::string, std::string> text;  // root string attributes (version, engine, units, ...)
  std::size_t frames = 0, bodies = 0;
  double first_time = 0, last_time = 0;
  std::map<std::string, double> diagnostics;
};

// Opens `path` and reads every frame's datasets and the energy table, checking their shapes against
// each other. Throws InputError (key "file") naming what is missing, unreadable or inconsistent.
RunFileSummary read_run_file(const std::string& path);

// Reads frames `group`/000000 ... `group`/(count - 1) of `path`, laid out as RunWriter writes them, one
// at a time (each checked: shapes, checksums) and hands each to `take`. Throws InputError (key "file")
// naming what is missing or damaged.
void read_frames(const std::string& path, const std::string& group, std::size_t count,
                 const std::function<void(const Frame&)>& take);

// A file of named tables written by write_sample_tables (checkpoints, results.h5).
struct TableFile {
  std::map<std::string, std::string> metadata;  // root string attributes
  std::map<std::string, SampleTable> tables;
};
// Reads the root attributes and the named tables, checking each one's columns against `columns`
// (its attribute; an empty list takes the table's own, checking their number against the data). Throws
// InputError (key "file") naming what is missing, unreadable or different.
TableFile read_sample_tables(const std::string& path,
                             const std::map<std::string, std::vector<std::string>>& wanted);

// An object at the top of a file: a dataset or a group; a table is a dataset with the "columns" attribute
// write_sample_tables gives it.
struct H5Object {
  bool dataset = false, table = false;
  std::size_t members = 0;  // a group's
};
// The objects at the top of a file, by name. Throws InputError (key "file") if it is not a readable HDF5
// file. (`grainlab inspect` reads a file of tables whose names it does not know beforehand.)
std::map<std::string, H5Object> root_objects(const std::string& path);
// The same for the objects in `group` ("run/transport"), by name within it.
std::map<std::string, H5Object> group_objects(const std::string& path, const std::string& group);

// One frame of a height field over time, as GridSeriesWriter writes it (`/frames/NNNNNN`, ny rows of nx
// values, x along a row; `grainlab ripples hybrid --out`).
struct GridFrame {
  double time = 0;
  std::size_t nx = 0, ny = 0;
  std::vector<double> values;  // row after row
};
// Reads frame k (root_objects gives the number of frames: the members of "frames"). Throws InputError
// (key "file") naming what is missing, damaged, not 2-D or not finite.
GridFrame read_grid_frame(const std::string& path, std::size_t k);

// Stops with InputError (key "--restart") unless the file's metadata says it is a checkpoint of `kind`
// (`what` names it in the message), written by this grainlab version with these options (`mismatch` says
// what to pass instead).
void require_checkpoint(const TableFile& file, const std::string& path, const std::string& kind,
                        const std::string& what, const std::string& options, const std::string& mismatch);

}  // namespace grainlab
