#include "validate_command.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "binary_fingerprint.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "interrupt.hpp"
#include "number_ranges.hpp"
#include "option_scope.hpp"
#include "output_path.hpp"
#include "parallel.hpp"
#include "progress.hpp"
#include "suites.hpp"

extern char** environ;

namespace grainlab::cli {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
using validation::Report;
using validation::Suite;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

std::vector<const Suite*> chosen_suites(std::vector<std::string> names) {
  if (names.empty())
    for (const auto& s : validation::suites()) names.push_back(s.name);
  std::vector<const Suite*> chosen;
  for (const std::string& n : names) {
    const Suite* s = validation::find_suite(n);
    if (!s) {
      std::string known;
      for (const auto& k : validation::suites()) known += (known.empty() ? "" : ", ") + k.name;
      throw InputError({"--suite", 0}, n, "unknown suite; known suites: " + known);
    }
    chosen.push_back(s);
  }
  return chosen;
}

std::size_t failures(const Report& r) {
  return static_cast<std::size_t>(
      std::count_if(r.checks.begin(), r.checks.end(), [](auto& c) { return c.counts_as_failure(); }));
}

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Each finished suite's part of the report, kept in OUT/.parts until the whole report is written, beside a
// stamp of what made it: quick or full, the sand gun's checkpoint, and this program's own bytes (a rebuilt
// binary may give other numbers). With --resume a part whose stamp matches is taken instead of running its
// suite again, so an interrupted validation (hours in full mode) loses only the suites it was running. The
// suites are seeded, so a part taken is the part a new run would give.
class SuiteParts {
 public:
  SuiteParts(const validation::SuiteOptions& base, bool resume)
      : dir_(fs::path(base.out_dir) / ".parts"), resume_(resume) {
    if (parallel::rank() != 0) return;
    if (!resume) fs::remove_all(dir_);  // a stale part must not be taken by a later --resume
    fs::create_directories(dir_);
    stamp_ = fmt::format("grainlab validate part\nquick {}\nsand-gun checkpoint {}\nbinary {:016x}\n",
                         base.quick, base.sand_gun_checkpoint, binary_fingerprint());
  }
  fs::path part(const Suite& s) const { return dir_ / (s.name + ".json"); }
  // The suite's part from an earlier run with the same stamp (only with --resume).
  std::optional<Report> taken(const Suite& s) const {
    if (!resume_ || parallel::rank() != 0 || !fs::exists(stamp_path(s)) || !fs::exists(part(s))) return {};
    if (read_text(stamp_path(s)) != stamp_) return {};
    try {
      return validation::read_report_part(read_text(part(s)));
    } catch (const std::runtime_error&) {
      return {};  // damaged: run the suite again
    }
  }
  // Keeps the suite's part (written here unless a child process wrote it) and stamps it as whole.
  void keep(const Suite& s, const Report* r) const {
    if (parallel::rank() != 0) return;
    if (r) write_file_atomically(part(s).string(), validation::report_part_json(*r));
    write_file_atomically(stamp_path(s).string(), stamp_);
  }
  void clear() const {
    if (parallel::rank() == 0) fs::remove_all(dir_);
  }

 private:
  fs::path stamp_path(const Suite& s) const { return dir_ / (s.name + ".stamp"); }
  fs::path dir_;
  bool resume_;
  std::string stamp_;
};

void say_taken(bool speak, const Suite& s, const Report& r, const SuiteParts& parts) {
  if (speak)
    fmt::print(stderr, "suite {}: {} checks, {} failed (taken from the interrupted run: {})\n", s.name,
               r.checks.size(), failures(r), parts.part(s).string());
}

// The suites one after the other in this process (under mpirun every rank runs them and the ranks share
// each ensemble; rank 0 speaks).
Report run_here(const std::vector<const Suite*>& chosen, const validation::SuiteOptions& base, bool speak,
                const SuiteParts* parts) {
  Report report;
  validation::SuiteOptions opt = base;
  ProgressBar bar(speak, "runs");
  if (speak) {
    opt.log = [&bar](const std::string& line) {
      bar.finish();
      fmt::print(stderr, "  {}\n", line);
    };
    opt.progress = [&bar](std::size_t done, std::size_t total) { bar.update(double(done), double(total)); };
  }
  for (const Suite* s : chosen) {
    // (Rank 0 reads the parts; under mpirun every rank must skip the same suites, whose ensembles they
    // share.)
    std::optional<Report> taken = parts ? parts->taken(*s) : std::nullopt;
    if (parts && parallel::any_all(taken.has_value())) {
      if (taken) say_taken(speak, *s, *taken, *parts), report.append(std::move(*taken));
      continue;
    }
    if (speak) fmt::print(stderr, "suite {}: {}\n", s->name, s->description);
    const auto start = Clock::now();
    Report one;
    s->run(one, opt);
    one.times.push_back({s->name, seconds_since(start)});
    if (parts) parts->keep(*s, &one);
    report.append(std::move(one));
  }
  bar.finish();
  return report;
}

std::string last_lines(const fs::path& p, std::size_t n) {
  std::vector<std::string> lines;
  std::istringstream in(read_text(p));
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::string tail;
  for (std::size_t k = lines.size() > n ? lines.size() - n : 0; k < lines.size(); ++k)
    tail += "    " + lines[k] + "\n";
  return tail;
}

struct Child {
  pid_t pid = 0;
  std::size_t index = 0;  // into the chosen suites
  Clock::time_point start;
};

// Starts `grainlab validate --suite NAME --part FILE` with its output going to `log`.
pid_t spawn_suite(const Suite& s, const validation::SuiteOptions& base, const fs::path& part,
                  const fs::path& log) {
  // /proc/self/exe runs this very program even when its file has been replaced since it started (a
  // rebuild during a long validation left "grainlab (deleted)", and no suite could start).
  const std::string exe = "/proc/self/exe";
  std::vector<std::string> args = {fs::read_symlink(exe).string(),
                                   "validate",
                                   "--suite",
                                   s.name,
                                   "--out",
                                   base.out_dir,
                                   "--part",
                                   part.string()};
  if (base.quick) args.push_back("--quick");
  if (!base.sand_gun_checkpoint.empty())
    args.insert(args.end(), {"--sand-gun-checkpoint", base.sand_gun_checkpoint});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  // A process group of its own: a Ctrl-C at the terminal reaches the suite once, passed on by this
  // process (ChildHold), which then waits for nothing more; `kill` of this process reaches it the same way.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid = 0;
  const int err = posix_spawn(&pid, exe.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) throw std::runtime_error(fmt::format("cannot start {}: {}", args[0], std::strerror(err)));
  return pid;
}

// What a suite whose process died without a report part contributes: one failing check that says so.
Report lost_suite(const Suite& s, int status, const fs::path& log) {
  Report r;
  const std::string how = WIFSIGNALED(status) ? fmt::format("was killed by signal {}", WTERMSIG(status))
                                              : fmt::format("ended with status {}", WEXITSTATUS(status));
  r.expect_below(fmt::format("validate/{}/completed", s.name), "native", 1, 0,
                 fmt::format("the suite's process {} before handing back its results; its output is in {}",
                             how, log.string()));
  return r;
}

// The suites in `jobs` processes at once, longest first; the parts are put together in the chosen order.
Report run_in_processes(const std::vector<const Suite*>& chosen, const validation::SuiteOptions& base,
                        bool speak, std::size_t jobs, const SuiteParts& parts) {
  const fs::path logs = fs::path(base.out_dir) / "logs";
  fs::create_directories(logs);
  std::vector<Report> results(chosen.size());
  std::size_t next = 0, done = 0;
  std::vector<std::size_t> queue;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    if (std::optional<Report> taken = parts.taken(*chosen[k])) {
      say_taken(speak, *chosen[k], *taken, parts);
      results[k] = std::move(*taken), ++done;
    } else {
      queue.push_back(k);
    }
  }
  std::stable_sort(queue.begin(), queue.end(), [&](std::size_t a, std::size_t b) {
    return chosen[a]->quick_minutes > chosen[b]->quick_minutes;
  });
  if (speak)
    fmt::print(stderr, "{} suites in {} processes at once; each suite's progress lines go to {}/\n",
               chosen.size(), jobs, logs.string());
  std::map<pid_t, Child> running;
  std::map<pid_t, ChildHold> held;  // sent this process's SIGINT, SIGTERM or SIGHUP
  // The bar and its estimate count each suite by its typical time (quick form; a suite's full form takes
  // longer in much the same order), so that the long suites, which start first, do not make the short
  // ones behind them look as long. Told once at the start, so the first suite done gives an estimate.
  double work = 0, work_total = 0;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    work_total += chosen[k]->quick_minutes;
    if (std::find(queue.begin(), queue.end(), k) == queue.end())  // taken from a stopped run's parts
      work += chosen[k]->quick_minutes;
  }
  ProgressBar bar(speak, "suites");
  bar.update_weighted(double(done), double(chosen.size()), work, work_total);
  while (done < chosen.size()) {
    while (running.size() < jobs && next < queue.size()) {
      const std::size_t k = queue[next++];
      const Suite& s = *chosen[k];
      const pid_t pid = spawn_suite(s, base, parts.part(s), logs / (s.name + ".log"));
      running[pid] = {pid, k, Clock::now()};
      held.emplace(pid, ChildHold(pid));
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) throw std::runtime_error("waiting for a suite's process failed");
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const Child c = it->second;
    running.erase(it), held.erase(pid);
    const Suite& s = *chosen[c.index];
    const fs::path part = parts.part(s), log = logs / (s.name + ".log");
    const bool reported = WIFEXITED(status) && WEXITSTATUS(status) <= 1 && fs::exists(part);
    results[c.index] = reported ? validation::read_report_part(read_text(part)) : lost_suite(s, status, log);
    if (reported) parts.keep(s, nullptr);
    ++done;
    if (speak) {
      bar.finish();
      fmt::print(stderr, "suite {}: {} checks, {} failed ({:.0f} s)\n", s.name,
                 results[c.index].checks.size(), failures(results[c.index]), seconds_since(c.start));
      if (!reported)
        fmt::print(stderr, "  its process stopped early; the end of its output:\n{}", last_lines(log, 15));
    }
    work += s.quick_minutes;
    bar.update_weighted(double(done), double(chosen.size()), work, work_total);
  }
  bar.finish();
  Report report;
  for (Report& r : results) report.append(std::move(r));
  return report;
}

std::size_t job_count(int asked, std::size_t suites) {
  if (parallel::size() > 1) return 1;  // under mpirun the ranks share each suite instead
  std::size_t jobs = asked > 0 ? static_cast<std::size_t>(asked) : std::thread::hardware_concurrency();
  return std::clamp<std::size_t>(jobs, 1, std::max<std::size_t>(suites, 1));
}

}  // namespace

void ValidateCommand::add(CLI::App& app) {
  cmd = app.add_subcommand("validate", "run validation suites; exit 0 only if every check passes");
  cmd->add_option("--suite", suites, "suite to run (repeatable; default: all)");
  cmd->add_option("--out,-o", out, "report folder (report.md, report.json, plots)")
      ->default_val("report")  // before the check: a default is checked where it is set, at every start
      ->check(cli::output_folder());
  cmd->add_flag("--quick", quick, "shorter versions of long checks (for CI)");
  cmd->add_flag("--quiet,-q", quiet, "no progress lines");
  cmd->add_flag(
      "--resume", resume,
      "continue an interrupted validation into the same --out: the suites it finished (same options, "
      "same binary) are taken from OUT/.parts, the rest are run (the impacts, loaded-die and "
      "tumbling-polygon suites from the runs they had finished)");
  cmd->add_option("--jobs,-j", jobs,
                  "suites run at once, each in its own process (0: one per core; under mpirun always 1)")
      ->default_val(0)
      ->check(cli::in_range(0, 256));
  cmd->add_option("--sand-gun-checkpoint", sand_gun_checkpoint,
                  "impacts-3d (full): keep the 20,000-sphere sand-gun bed and its impacts in this HDF5 file, "
                  "as `grainlab sand-gun --runs 10 --checkpoint FILE` does; a file that command filled is "
                  "reused, so the hours of its bed and 90 impacts are not spent again; each Table 3.1 "
                  "case's impacts are kept beside it (FILE.case-X-ENGINE.h5), so a stopped suite continues")
      ->check(cli::output_file());
  cmd->add_flag("--list", list,
                "name the suites (with --suite: those), their typical time in quick form and what each "
                "checks; run nothing");
  // Internal: how a --jobs parent asks a child for its part of the report.
  cmd->add_option("--part", part, "")->group("");
}

int ValidateCommand::dispatch() const {
  if (!*cmd) return -1;
  const std::vector<const Suite*> chosen = chosen_suites(suites);
  if (list) {
    if (parallel::rank() == 0) {
      fmt::print("{:<17} {:>9}  {}\n", "suite", "quick", "what it checks (the full form takes longer)");
      for (const Suite* s : chosen)
        fmt::print("{:<17} {:>5.2f} min  {}\n", s->name, s->quick_minutes, s->description);
    }
    return 0;
  }
  check_output_path("--out", out, true);  // the default, which the option's own check does not see
  const bool sand_gun =
      std::any_of(chosen.begin(), chosen.end(), [](const Suite* s) { return s->name == "impacts-3d"; });
  if (!sand_gun)
    refuse_if_given(cmd->get_option("--sand-gun-checkpoint"),
                    "is for the impacts-3d suite, which --suite leaves out");
  if (parallel::rank() == 0) fs::create_directories(out);
  const bool speak = !quiet && parallel::rank() == 0;
  validation::SuiteOptions base;
  base.quick = quick, base.out_dir = out, base.sand_gun_checkpoint = sand_gun_checkpoint;
  // The suites' long ensembles as they go, by quick or full and by this binary (a rebuilt one may give
  // other numbers): kept for --resume in the parts folder, cleared with it.
  base.ensembles_dir = (fs::path(out) / ".parts" /
                        fmt::format("ensembles-{}-{:016x}", quick ? "quick" : "full", binary_fingerprint()))
                           .string();
  if (!part.empty()) {  // (a child of --jobs: its parent made the folders)
    const Report r = run_here(chosen, base, speak, nullptr);
    if (parallel::rank() == 0) write_file_atomically(part, validation::report_part_json(r));
    return r.passed() ? 0 : 1;
  }
  const std::size_t processes = job_count(jobs, chosen.size());
  const SuiteParts parts(base, resume);
  if (parallel::rank() == 0) fs::create_directories(base.ensembles_dir);
  const Report report = processes > 1 ? run_in_processes(chosen, base, speak, processes, parts)
                                      : run_here(chosen, base, speak, &parts);
  if (parallel::rank() != 0) return report.passed() ? 0 : 1;
  validation::write_report(report, out);
  parts.clear();
  const std::size_t failed = failures(report), limited = static_cast<std::size_t>(std::count_if(
                                                   report.checks.begin(), report.checks.end(), [](auto&c) {
                                                     return !c.passed && !c.counts_as_failure();
                                                   }));
  fmt::print("{}: {} checks, {} failed, {} documented engine limitations; report in {}/report.md\n",
             report.passed() ? "PASSED" : "FAILED", report.checks.size(), failed, limited, out);
  return report.passed() ? 0 : 1;
}

}  // namespace grainlab::cli
