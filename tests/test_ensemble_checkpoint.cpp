// An ensemble kept in a checkpoint file (validation/ensemble_checkpoint.hpp): rows come back bit for bit,
// a continued ensemble runs only what the file lacks and ends with the table of one that never stopped,
// and a file written for another ensemble is refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "cli_helpers.hpp"
#include "ensemble_checkpoint.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"

namespace {

using namespace cli_test;
using grainlab::InputError;
using grainlab::validation::EnsembleCheckpoint;
using grainlab::validation::read_ensemble_checkpoint;
using grainlab::validation::run_checkpointed_ensemble;
using grainlab::validation::run_ensemble;
using grainlab::validation::write_ensemble_checkpoint;

EnsembleCheckpoint checkpoint_in(const Dir& d) {
  return {(d.path / "ck.h5").string(), "test checkpoint", "ensemble 1", "pass ensemble 1", "--checkpoint", 0};
}

// Run i's row: a few numbers of its own, then zeros (as an impact's unused ejecta slots).
std::vector<double> row_of(std::size_t i) {
  std::vector<double> r(6, 0.0);
  for (std::size_t k = 0; k <= i % 4; ++k) r[k] = std::sin(1.0 + static_cast<double>(i * 7 + k));
  return r;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(EnsembleCheckpoint, RowsComeBackBitForBit) {
  Dir d;
  const EnsembleCheckpoint c = checkpoint_in(d);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::map<std::size_t, std::vector<double>> rows = {{0, {1.5, 0.0, 0.0, 0.0}},
                                                           {2, {0.0, 0.0, 0.0, -0.0}},
                                                           {7, {nan, 1e-300, 0.0, nan}},
                                                           {9, {0.0, 0.0, 0.0, 0.0}}};
  write_ensemble_checkpoint(c, 4, rows);
  const auto back = read_ensemble_checkpoint(c, 4);
  ASSERT_EQ(back.size(), rows.size());
  for (const auto& [i, r] : rows) EXPECT_TRUE(same_bits(back.at(i), r)) << "run " << i;
  EnsembleCheckpoint none = c;
  none.path = (d.path / "none.h5").string();
  EXPECT_TRUE(read_ensemble_checkpoint(none, 4).empty());
}

TEST(EnsembleCheckpoint, ContinuesWithOnlyTheMissingRuns) {
  Dir d;
  const EnsembleCheckpoint c = checkpoint_in(d);
  std::size_t calls = 0;
  auto run = [&](std::size_t i) { return ++calls, row_of(i); };
  const auto straight = run_ensemble(11, 6, row_of);
  run_checkpointed_ensemble(4, 6, run, c);  // a first run of 4, then the same to 11
  EXPECT_EQ(calls, 4u);
  std::vector<std::size_t> told;  // the progress bar hears the kept runs first, then each run as it ends
  const auto continued =
      run_checkpointed_ensemble(11, 6, run, c, [&](std::size_t done, std::size_t) { told.push_back(done); });
  EXPECT_EQ(calls, 11u);
  EXPECT_EQ(told, (std::vector<std::size_t>{4, 5, 6, 7, 8, 9, 10, 11}));
  ASSERT_EQ(continued.size(), straight.size());
  for (std::size_t i = 0; i < straight.size(); ++i) EXPECT_TRUE(same_bits(continued[i], straight[i]));
  EXPECT_EQ(read_ensemble_checkpoint(c, 6).size(), 11u);
  // Fewer runs than the file holds: taken from it, nothing run.
  const auto fewer = run_checkpointed_ensemble(3, 6, run, c);
  EXPECT_EQ(calls, 11u);
  ASSERT_EQ(fewer.size(), 3u);
  EXPECT_TRUE(same_bits(fewer[2], straight[2]));
}

TEST(EnsembleCheckpoint, AnotherEnsemblesFileIsRefusedByName) {
  Dir d;
  EnsembleCheckpoint c = checkpoint_in(d);
  write_ensemble_checkpoint(c, 6, {{0, row_of(0)}});
  auto refusal = [&](const EnsembleCheckpoint& k, std::size_t width) -> std::string {
    try {
      read_ensemble_checkpoint(k, width);
    } catch (const InputError& e) {
      EXPECT_EQ(e.key(), "--checkpoint");
      EXPECT_EQ(e.where().file, c.path);
      return e.message();
    }
    return "accepted";
  };
  EnsembleCheckpoint other = c;
  other.fingerprint = "ensemble 2";
  EXPECT_EQ(refusal(other, 6), "pass ensemble 1");
  EXPECT_EQ(refusal(c, 7), "holds rows of 6 numbers, this run's have 7");
  // Another kind of file with the same tables and fingerprint.
  grainlab::write_sample_tables(c.path,
                                {{"runs", "", {"run", "first", "count"}, {}}, {"values", "", {"value"}, {}}},
                                {{"kind", "grainlab-other/1"},
                                 {"grainlab_version", GRAINLAB_VERSION},
                                 {"options", c.fingerprint},
                                 {"width", "6"}});
  EXPECT_EQ(refusal(c, 6).rfind("is not a test checkpoint", 0), 0u);
  { std::ofstream(c.path) << "not HDF5"; }
  EXPECT_NE(refusal(c, 6), "accepted");
}

}  // namespace
