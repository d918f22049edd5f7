// Run under mpirun by ctest (1, 2 and 3 ranks): an ensemble of loaded-die throws dealt out over the
// ranks gives, on every rank, exactly (bitwise) the table that throwing them one by one gives.
#include <fmt/format.h>

#include <cstdlib>

#include "ensemble.hpp"
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
  if (parallel::rank() == 0)
    fmt::print("{} throws on {} ranks: {}\n", throws, parallel::size(), failures ? "MISMATCH" : "identical");
  parallel::finalize();
  return failures ? 1 : 0;
}
