#pragma once
// Which commands spread their work over MPI ranks. The others run on rank 0 alone under mpirun: every
// rank running them printed their output (and their one JSON object) once per rank and wrote the same
// files side by side.
#include <CLI/CLI.hpp>
#include <set>
#include <string>

namespace grainlab::cli {

// The subcommand the command line chose, as its words: "saltation dem".
inline std::string chosen_command(const CLI::App& app) {
  std::string path;
  const CLI::App* a = &app;
  while (!a->get_subcommands().empty()) {
    a = a->get_subcommands().front();
    path += (path.empty() ? "" : " ") + a->get_name();
  }
  return path;
}

// "the other MPI rank stops" / "the other 3 MPI ranks stop", for `ranks` ranks in all.
inline std::string other_ranks_stop(int ranks) {
  return ranks == 2 ? "the other MPI rank stops"
                    : "the other " + std::to_string(ranks - 1) + " MPI ranks stop";
}

inline bool command_uses_ranks(const std::string& command) {
  static const std::set<std::string> spread = {"run",
                                               "validate",
                                               "impact",
                                               "splash",
                                               "sand-gun",
                                               "saltation dem",
                                               "ripples lattice",
                                               "ripples hybrid",
                                               "ripples hybrid-flux",
                                               "ripples hybrid-focal",
                                               "bench bed",
                                               "bench bed3d"};
  return spread.count(command) > 0;
}

}  // namespace grainlab::cli
