#include "plot_script.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#ifndef GRAINLAB_SOURCE_DIR
#define GRAINLAB_SOURCE_DIR "."
#endif

extern char** environ;

namespace grainlab::validation {

namespace fs = std::filesystem;

namespace {
// The last non-empty line of a file (a failed script's error, at the end of its traceback).
std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last;
}

// Runs argv[0] with argv, stdout to /dev/null and stderr to a temporary file; returns the exit status (-1
// when it could not run or did not exit normally) and, when it failed, the last line it wrote to stderr,
// so that a plot that fails says why. (posix_spawn, not std::system: no shell, so no path needs quoting.)
std::pair<int, std::string> run_quietly(const std::vector<std::string>& argv) {
  std::string err = (fs::temp_directory_path() / "grainlab-plot-XXXXXX").string();
  const int err_fd = mkstemp(err.data());
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
  if (err_fd >= 0)
    posix_spawn_file_actions_adddup2(&io, err_fd, 2);
  else
    posix_spawn_file_actions_addopen(&io, 2, "/dev/null", O_WRONLY, 0);
  std::vector<char*> v;
  for (const std::string& s : argv) v.push_back(const_cast<char*>(s.c_str()));
  v.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, v[0], &io, nullptr, v.data(), environ);
  posix_spawn_file_actions_destroy(&io);
  int status = -1;
  if (spawned == 0) {
    int raw = 0;
    pid_t waited = -1;
    while ((waited = waitpid(pid, &raw, 0)) < 0 && errno == EINTR) {
    }
    if (waited == pid && WIFEXITED(raw)) status = WEXITSTATUS(raw);
  }
  std::string why;
  if (err_fd >= 0) {
    close(err_fd);
    if (status != 0) why = last_line(err);
    std::error_code ec;
    fs::remove(err, ec);
  }
  return {status, why};
}
}  // namespace

namespace {
const std::string kPython = "/usr/bin/python3";
std::string script_path(const std::string& script) {
  return std::string(GRAINLAB_SOURCE_DIR) + "/tools/" + script;
}
}  // namespace

std::string missing_for_plots(const std::string& script) {
  for (const std::string& needed : {kPython, script_path(script)})
    if (!fs::exists(needed)) return "no " + needed;
  return "";
}

std::string run_plot_script(const std::string& script, const std::vector<std::string>& args) {
  if (std::string missing = missing_for_plots(script); !missing.empty()) return missing;
  const std::string python = kPython, path = script_path(script);
  std::vector<std::string> argv{python, path};
  argv.insert(argv.end(), args.begin(), args.end());
  const auto [status, why] = run_quietly(argv);
  if (status == 0) return "";
  return fmt::format("{} {} exited with status {}{}", python, path, status, why.empty() ? "" : ": " + why);
}

std::string draw_png(const std::string& script, std::vector<std::string> args, const std::string& png) {
  // matplotlib takes the format from the name, so the temporary name ends in .png too.
  const std::string part = fs::path(png).replace_extension(".part.png").string();
  args.push_back(part);
  const std::string why = run_plot_script(script, args);
  std::error_code ec;
  if (why.empty() && fs::exists(part, ec)) {
    fs::rename(part, png, ec);
    if (!ec) return "";
  }
  fs::remove(part, ec);
  return why.empty() ? "the script wrote no " + part : why;
}

}  // namespace grainlab::validation
