#include "parallel.hpp"

#include <mpi.h>

#include <cstdlib>

namespace grainlab::parallel {

namespace {
bool started = false;
int my_rank = 0, n_ranks = 1;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}
}  // namespace

void init_if_launched(int* argc, char*** argv) {
  if (started || !launched_by_mpi()) return;
  MPI_Init(argc, argv);
  started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &my_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &n_ranks);
}

void finalize() {
  if (started) MPI_Finalize();
  started = false;
}

int rank() {
  return my_rank;
}
int size() {
  return n_ranks;
}

void sum_all(std::vector<double>& values) {
  if (!started || n_ranks == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
}

}  // namespace grainlab::parallel
