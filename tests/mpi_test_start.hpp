#pragma once
// The start every MPI test program shares: MPI started when launched by mpirun, and the rank count ctest
// asked for (argv[1]) checked against the one it got; returns 1 (a failure) if they differ.
#include <fmt/format.h>

#include <cstdlib>

#include "parallel.hpp"

namespace grainlab::testing {

inline int start_mpi_test(int& argc, char**& argv) {
  parallel::init_if_launched(&argc, &argv);
  const int expected_ranks = argc > 1 ? std::atoi(argv[1]) : 1;
  if (parallel::size() == expected_ranks) return 0;
  fmt::print(stderr, "expected {} ranks, running on {}\n", expected_ranks, parallel::size());
  return 1;
}

}  // namespace grainlab::testing
