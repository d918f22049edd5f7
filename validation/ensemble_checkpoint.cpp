#include "ensemble_checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "h5_input.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "parallel.hpp"

namespace grainlab::validation {

namespace {

constexpr const char* kKind = "grainlab-ensemble-checkpoint/1";
// Each finished run: its index, and where its row starts in `values` and how many of its numbers are
// kept there (the rest of the row is zeros).
const std::vector<std::string> kRunColumns = {"run", "first", "count"};
const std::vector<std::string> kValueColumns = {"value"};
// Runs each rank takes in the first round: one, since a run may take minutes (a 3-D impact, a hybrid
// ripple run) and a stop loses the round under way. Rounds that end within kShortRound seconds double
// it, up to kMostPerRank, so that ensembles of runs of milliseconds (die throws) meet at a round's end
// about once in that time, not after every run.
constexpr std::size_t kFirstPerRank = 1, kMostPerRank = 1 << 16;
constexpr double kShortRound = 2.0;

// A whole number in [0, limit), or nothing.
bool whole_below(double v, double limit) {
  return v >= 0 && v < limit && v == std::floor(v);
}

}  // namespace

void write_ensemble_checkpoint(const EnsembleCheckpoint& c, std::size_t width,
                               const std::map<std::size_t, std::vector<double>>& rows) {
  SampleTable runs{
      "runs", "each finished run: its index, and its numbers' place in `values`", kRunColumns, {}};
  SampleTable values{
      "values", "the finished runs' rows, one after the other, less trailing zeros", kValueColumns, {}};
  for (const auto& [i, row] : rows) {
    if (row.size() != width) throw std::logic_error("ensemble checkpoint: a row of the wrong width");
    std::size_t kept = width;
    while (kept > 0 && row[kept - 1] == 0 && !std::signbit(row[kept - 1])) --kept;
    runs.rows.push_back(
        {static_cast<double>(i), static_cast<double>(values.rows.size()), static_cast<double>(kept)});
    for (std::size_t k = 0; k < kept; ++k) values.rows.push_back({row[k]});
  }
  write_sample_tables(c.path, {runs, values},
                      {{"kind", kKind},
                       {"grainlab_version", GRAINLAB_VERSION},
                       {"options", c.fingerprint},
                       {"width", std::to_string(width)},
                       {"what", c.what}});
}

std::map<std::size_t, std::vector<double>> read_ensemble_checkpoint(const EnsembleCheckpoint& c,
                                                                    std::size_t width) {
  std::map<std::size_t, std::vector<double>> rows;
  if (!std::filesystem::exists(c.path)) return rows;
  auto refuse = [&](const std::string& why) { throw InputError({c.path, 0}, c.option, why); };
  TableFile file;
  try {
    file = read_sample_tables(c.path, {{"runs", kRunColumns}, {"values", kValueColumns}});
    require_checkpoint(file, c.path, kKind, c.what, c.fingerprint, c.mismatch);
  } catch (const InputError& e) {
    refuse(e.message());
  }
  if (file.metadata["width"] != std::to_string(width))
    refuse(fmt::format("holds rows of {} numbers, this run's have {}", file.metadata["width"], width));
  const auto& values = file.tables.at("values").rows;
  double next = 0;  // the rows lie one after the other, in the order of their runs
  for (const auto& r : file.tables.at("runs").rows) {
    if (!whole_below(r[0], 1e12) || !whole_below(r[2], static_cast<double>(width) + 1) || r[1] != next ||
        r[1] + r[2] > static_cast<double>(values.size()))
      refuse(fmt::format("has a damaged record of run {}", r[0]));
    const auto i = static_cast<std::size_t>(r[0]);
    if (!rows.empty() && i <= rows.rbegin()->first) refuse("has its runs out of order");
    std::vector<double> row(width, 0.0);
    for (std::size_t k = 0; k < static_cast<std::size_t>(r[2]); ++k)
      row[k] = values[static_cast<std::size_t>(r[1]) + k][0];
    rows.emplace(i, std::move(row));
    next += r[2];
  }
  if (next != static_cast<double>(values.size())) refuse("has numbers of no run");
  return rows;
}

std::vector<std::vector<double>> run_checkpointed_ensemble(
    std::size_t runs, std::size_t width, const std::function<std::vector<double>(std::size_t)>& run,
    const EnsembleCheckpoint& c, const EnsembleProgress& progress) {
  if (c.path.empty()) return run_ensemble(runs, width, run, progress);
  std::map<std::size_t, std::vector<double>> kept = read_ensemble_checkpoint(c, width);
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < runs; ++i)
    if (!kept.count(i)) todo.push_back(i);
  const std::size_t ranks = parallel::size(), rank = parallel::rank();
  std::size_t per_rank = kFirstPerRank;
  using Clock = std::chrono::steady_clock;
  auto written = Clock::now();
  if (progress && runs > 0) progress(runs - todo.size(), runs);
  for (std::size_t start = 0, n = 0; start < todo.size(); start += n) {
    n = std::min(ranks * per_rank, todo.size() - start);
    const auto began = Clock::now();
    const std::size_t before = runs - todo.size() + start;
    // run_ensemble deals the round out over the ranks and gathers it (its first word, 0 done, is told
    // above or by the round before).
    const auto round = run_ensemble(
        n, width, [&](std::size_t k) { return run(todo[start + k]); },
        [&](std::size_t done, std::size_t) {
          if (progress && done > 0) progress(std::min(runs, before + done), runs);
        });
    // (The slowest rank's time, so that every rank sizes the next round alike.)
    const double took = parallel::max_all(std::chrono::duration<double>(Clock::now() - began).count());
    if (took < kShortRound) per_rank = std::min(2 * per_rank, kMostPerRank);
    for (std::size_t k = 0; k < n; ++k) kept[todo[start + k]] = round[k];
    const bool last = start + n == todo.size();
    const double since = std::chrono::duration<double>(Clock::now() - written).count();
    if (rank == 0 && (last || since >= c.seconds_between_writes)) {
      write_ensemble_checkpoint(c, width, kept);
      written = Clock::now();
    }
  }
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < runs; ++i) rows.push_back(kept.at(i));
  return rows;
}

}  // namespace grainlab::validation
