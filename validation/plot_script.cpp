#include "plot_script.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <filesystem>

#ifndef GRAINLAB_SOURCE_DIR
#define GRAINLAB_SOURCE_DIR "."
#endif

extern char** environ;

namespace grainlab::validation {

namespace fs = std::filesystem;

namespace {
// The exit status of argv[0] run with argv, stdout and stderr to /dev/null; -1 when it could not run or
// did not exit normally. (posix_spawn, not std::system: no shell, so no path needs quoting.)
int run_quietly(const std::vector<std::string>& argv) {
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&io, 2, "/dev/null", O_WRONLY, 0);
  std::vector<char*> v;
  for (const std::string& s : argv) v.push_back(const_cast<char*>(s.c_str()));
  v.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, v[0], &io, nullptr, v.data(), environ);
  posix_spawn_file_actions_destroy(&io);
  if (spawned != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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
  const int status = run_quietly(argv);
  if (status == 0) return "";
  return fmt::format("{} {} exited with status {}", python, path, status);
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
