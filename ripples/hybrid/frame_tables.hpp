#pragma once
// A ripple run's frames (their statistics, profiles and surface sizes) as checkpoint tables, and back: what
// a continued run needs, besides the run's own state (RippleRun::save), to end with the trends and history
// of a run that was never stopped. The CLI's checkpoints and the hybrid suite's kept ripple run use them.
#include <map>
#include <string>
#include <vector>

#include "h5_output.hpp"
#include "ripple_run.hpp"

namespace grainlab::ripples::hybrid {

// The columns of a frame's row, in order (the CLI's "history" table has the same).
const std::vector<std::string>& frame_history_columns();
std::vector<double> frame_history_row(const BedFrame& f);

// The tables prefix + "history", "profiles" and, on a bed of several sizes, "size_profiles" (grids nx wide).
std::vector<SampleTable> frame_tables(const std::vector<BedFrame>& frames, std::size_t nx, bool sizes,
                                      const std::string& prefix);
// The names of those tables, each with no columns (any are read; frames_of_tables checks them).
std::map<std::string, std::vector<std::string>> frame_table_names(bool sizes, const std::string& prefix);
// The frames back, with key-point spacing dx (d). The history may have the first columns of
// frame_history_columns() that an older build wrote: the frames read NaN for the rest. Throws
// std::invalid_argument for missing tables, unknown columns, or profiles and sizes for other frames.
std::vector<BedFrame> frames_of_tables(const std::map<std::string, SampleTable>& tables, std::size_t nx,
                                       double dx, bool sizes, const std::string& prefix);

}  // namespace grainlab::ripples::hybrid
