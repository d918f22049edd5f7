#pragma once
// `grainlab validate`: runs validation suites and writes the report. With --jobs N (default: one per
// core) the suites run in N processes of this same program at once, each handing its part of the report
// back as a file; the report is the same as a serial run's, suite order included. Each finished suite's part
// is kept in OUT/.parts until the report is written, so --resume continues an interrupted validation.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace grainlab::cli {

struct ValidateCommand {
  std::vector<std::string> suites;
  std::string out = "report";
  std::string part;  // internal: write this process's part of the report here instead of the report
  std::string sand_gun_checkpoint;  // impacts-3d: the sand gun's bed and impacts, kept and reused
  bool quick = false, quiet = false;
  bool resume = false;  // take the suites an interrupted run into the same --out finished, run the rest
  bool list = false;    // name the suites, their typical quick times and what they check; run nothing
  int jobs = 0;         // 0: one per core (1 under mpirun, where the ranks share each suite's ensembles)

  CLI::App* cmd = nullptr;
  void add(CLI::App& app);
  // Runs the command if it was asked for; -1 if it was not.
  int dispatch() const;
};

}  // namespace grainlab::cli
