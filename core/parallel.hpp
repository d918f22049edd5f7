#pragma once
// The process's place among MPI ranks. grainlab starts MPI only when it was launched by mpirun (or
// another MPI launcher): a plain `grainlab ...` is one process with rank 0 of 1 and never touches MPI.
#include <vector>

namespace grainlab::parallel {

// Calls MPI_Init when the environment shows an MPI launcher (Open MPI, PMI, PMIx, Hydra).
void init_if_launched(int* argc, char*** argv);
// Calls MPI_Finalize if init_if_launched started MPI.
void finalize();
int rank();
int size();
// Element-wise sum over all ranks, result on every rank (nothing to do on one process).
void sum_all(std::vector<double>& values);

}  // namespace grainlab::parallel
