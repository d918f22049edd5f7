#pragma once
// A command that writes a run file RUN.h5 draws its plot beside it (RUN + suffix + .png) with one of
// tools/'s matplotlib scripts. A machine without Debian's matplotlib gets a note and the HDF5 alone; an
// existing PNG is kept unless `force`; with `json` the notes go to stderr, so stdout stays one JSON object.
#include <string>
#include <vector>

namespace grainlab::cli {

// Runs tools/SCRIPT ARGS... PNG and says what became of it. `what` names the plot in the note.
void draw_plot_beside(const std::string& h5, const std::string& suffix, const std::string& script,
                      const std::vector<std::string>& args, bool force, bool json, const std::string& what);

}  // namespace grainlab::cli
