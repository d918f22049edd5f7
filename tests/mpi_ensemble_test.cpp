// Run under mpirun by ctest (1, 2 and 3 ranks): an ensemble of loaded-die throws dealt out over the
// ranks gives, on every rank, exactly (bitwise) the table that throwing them one by one gives; so does a
// checkpointed ensemble continued from a file that holds some of its throws, which throws only the rest.
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "ensemble.hpp"
#include "ensemble_checkpoint.hpp"
#include "loaded_die.hpp"
#include "mpi_test_start.hpp"
#include "parallel.hpp"

using namespace grainlab;

int main(int argc, char** argv) {
  int failures = testing::start_mpi_test(argc, argv);
  const validation::Die2d die{0.3, 0.7, 0.8};
  const std::size_t throws = 13;  // not a multiple of 2 or 3: ranks get unequal shares
  auto one = [&](std::size_t i) {
    const auto t = validation::throw_die_2d("native", die, 42, i);
    return std::vector<double>{double(t.face_down), t.time};
  };
  const auto table = validation::run_ensemble(throws, 2, one);
  for (std::size_t i = 0; i < throws; ++i) {
    const auto serial = one(i);
    if (table[i] != serial) {
      fmt::print(stderr, "rank {}: throw {} gave ({}, {}) in the ensemble, ({}, {}) alone\n",
                 parallel::rank(), i, table[i][0], table[i][1], serial[0], serial[1]);
      ++failures;
    }
  }
  // A file holding throws 0, 3 and 4 (written by one rank before the others read it), continued to all.
  const validation::EnsembleCheckpoint ck{fmt::format("mpi-ensemble-{}.ck.h5", argc > 1 ? argv[1] : "1"),
                                          "test checkpoint",
                                          "die 0.3 0.7 0.8",
                                          "another die",
                                          "--checkpoint",
                                          0};
  if (parallel::rank() == 0) {
    std::filesystem::remove(ck.path);
    validation::write_ensemble_checkpoint(ck, 2, {{0, table[0]}, {3, table[3]}, {4, table[4]}});
  }
  parallel::barrier();
  std::vector<double> thrown{0};
  const auto continued = validation::run_checkpointed_ensemble(
      throws, 2, [&](std::size_t i) { return ++thrown[0], one(i); }, ck);
  parallel::sum_all(thrown);
  if (continued != table || thrown[0] != throws - 3) {
    fmt::print(stderr, "rank {}: the continued ensemble threw {} times, {} its table\n", parallel::rank(),
               thrown[0], continued == table ? "with" : "without");
    ++failures;
  }
  parallel::barrier();
  if (validation::read_ensemble_checkpoint(ck, 2).size() != throws) {
    fmt::print(stderr, "rank {}: the checkpoint does not hold every throw at the end\n", parallel::rank());
    ++failures;
  }
  parallel::barrier();
  if (parallel::rank() == 0) std::filesystem::remove(ck.path);
  if (parallel::rank() == 0)
    fmt::print("{} throws on {} ranks: {}\n", throws, parallel::size(), failures ? "MISMATCH" : "identical");
  parallel::finalize();
  return failures ? 1 : 0;
}
