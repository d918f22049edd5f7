#pragma once
// Runs one of tools/'s matplotlib scripts (Debian's python3) on a file grainlab wrote. A plot is an extra:
// a machine without python3 or matplotlib still gets every number, so a plot that cannot be drawn is
// reported to the caller, never thrown.
#include <string>
#include <vector>

namespace grainlab::validation {

// "" when /usr/bin/python3 and tools/SCRIPT are there; otherwise which of them is missing.
std::string missing_for_plots(const std::string& script);

// Runs /usr/bin/python3 tools/SCRIPT ARGS... with its output discarded. Returns "" when the script exited 0,
// otherwise why not (no python3, the script missing, its exit status).
std::string run_plot_script(const std::string& script, const std::vector<std::string>& args);

// Draws PNG with tools/SCRIPT ARGS... PNG (ARGS end with the script's own flag for its output, if it has
// one). The script writes a temporary file that is renamed to PNG once it is whole, so a failed plot leaves
// no file behind. Returns "" on success, otherwise why not.
std::string draw_png(const std::string& script, std::vector<std::string> args, const std::string& png);

}  // namespace grainlab::validation
