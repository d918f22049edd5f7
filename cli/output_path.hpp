#pragma once
// Output paths are checked when the command line is read, not when the first file is written: a run of
// hours must not end on a folder that does not exist or cannot be written (exit 2 at once instead, as for
// any bad value). A file's folder must exist; a folder's missing parents are made, so only the nearest
// existing ancestor must be a writable folder.
#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <string>

#include "input_error.hpp"

namespace grainlab::cli {

// What is wrong with `path` as an output file (folder = false) or folder; "" if nothing, or if it is empty
// (no output asked for).
inline std::string output_path_problem(const std::string& path, bool folder) {
  namespace fs = std::filesystem;
  if (path.empty()) return "";
  std::error_code ec;
  const fs::path p(path);
  if (!folder && fs::is_directory(p, ec)) return fmt::format("{}: is a folder; give a file name", path);
  if (folder && fs::exists(p, ec) && !fs::is_directory(p, ec))
    return fmt::format("{}: exists and is not a folder", path);
  fs::path parent = p.parent_path();
  if (parent.empty()) parent = ".";
  if (folder)
    while (!fs::exists(parent, ec) && parent.has_parent_path() && parent.parent_path() != parent)
      parent = parent.parent_path();
  if (!fs::exists(parent, ec)) return fmt::format("{}: its folder {} does not exist", path, parent.string());
  if (!fs::is_directory(parent, ec)) return fmt::format("{}: {} is not a folder", path, parent.string());
  if (::access(parent.c_str(), W_OK | X_OK) != 0)
    return fmt::format("{}: its folder {} cannot be written", path, parent.string());
  return "";
}

// CLI11 validators for output options (a failed check exits 2 with the option's name).
inline CLI::Validator output_file() {
  return CLI::Validator([](std::string& s) { return output_path_problem(s, false); }, "", "output file");
}
inline CLI::Validator output_folder() {
  return CLI::Validator([](std::string& s) { return output_path_problem(s, true); }, "", "output folder");
}

// The same for a path that does not come from an option of its own (a scene's [output] file), or for an
// option's default, which CLI11 checks only where it is set (when every command is built, in any folder).
inline void check_output_path(const std::string& key, const std::string& path, bool folder) {
  if (const std::string why = output_path_problem(path, folder); !why.empty())
    throw InputError({key, 0}, "", why);
}

}  // namespace grainlab::cli
