#pragma once
// The process's place among MPI ranks. grainlab starts MPI only when it was launched by mpirun (or
// another MPI launcher): a plain `grainlab ...` is one process with rank 0 of 1 and never touches MPI.
// The collectives below are what the native engine's domain decomposition needs; on one process they
// return their input.
#include <cstdint>
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
void sum_all(std::vector<std::uint64_t>& values);
double max_all(double value);
bool any_all(bool value);
// Every rank's vector, concatenated in rank order, on every rank.
std::vector<double> gather_all(const std::vector<double>& mine);
// Every rank's vector concatenated in rank order on rank 0 (empty elsewhere).
std::vector<double> gather_to_root(const std::vector<double>& mine);
// The same vector on every rank, from rank 0.
void broadcast(std::vector<double>& values);
// Sends send[q] to every rank q and returns what each rank sent to this one (sizes exchanged first).
std::vector<std::vector<double>> all_to_all(const std::vector<std::vector<double>>& send);
// Point-to-point exchange with known sizes: send[k] goes to rank to[k]; recv[k] (already sized) is
// filled from rank from[k]. At most one message per pair of ranks and direction.
void exchange(const std::vector<int>& to, const std::vector<std::vector<double>>& send,
              const std::vector<int>& from, std::vector<std::vector<double>>& recv);
void barrier();
// Ends every rank at once (MPI_Abort) when one rank fails alone, so the others do not wait forever in
// a collective; on one process, just returns.
void abort_all(int status);

}  // namespace grainlab::parallel
