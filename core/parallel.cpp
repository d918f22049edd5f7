#include "parallel.hpp"

#include <mpi.h>

#include <cstdlib>
#include <numeric>

namespace grainlab::parallel {

namespace {
bool started = false;
int my_rank = 0, n_ranks = 1;

bool launched_by_mpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(v)) return true;
  return false;
}
bool many() {
  return started && n_ranks > 1;
}
std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  std::partial_sum(counts.begin(), counts.end() - 1, d.begin() + 1);
  return d;
}
}  // namespace

void init_if_launched(int* argc, char*** argv) {
  if (started || !launched_by_mpi()) return;
  // Open MPI's shared-memory transport hands a message over 4 KB to the kernel to copy between processes
  // (cross-memory attach: a system call per message). The engines send one such message to each neighbour
  // every step (ghost positions: 14 KB for a 10,000-sphere bed on 2 ranks, 72 KB for 100,000), and on
  // virtual machines the system call costs more than copying through the shared FIFOs: measured 8-10 %
  // off a 2-rank step at both sizes (docs/parallel.md). A setting of the user's own wins (no overwrite);
  // other MPI libraries ignore the variable.
  setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "none", 0);
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
  if (!many() || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
}

void sum_all(std::vector<std::uint64_t>& values) {
  if (!many() || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_UINT64_T, MPI_SUM,
                MPI_COMM_WORLD);
}

double max_all(double value) {
  if (many()) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

bool any_all(bool value) {
  int v = value ? 1 : 0;
  if (many()) MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return v != 0;
}

std::vector<double> gather_all(const std::vector<double>& mine) {
  if (!many()) return mine;
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(n_ranks);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const std::vector<int> displ = displacements(counts);
  std::vector<double> all(static_cast<std::size_t>(displ.back() + counts.back()));
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displ.data(), MPI_DOUBLE,
                 MPI_COMM_WORLD);
  return all;
}

std::vector<double> gather_to_root(const std::vector<double>& mine) {
  if (!many()) return mine;
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(n_ranks);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<double> all;
  std::vector<int> displ(n_ranks, 0);
  if (my_rank == 0) {
    displ = displacements(counts);
    all.resize(static_cast<std::size_t>(displ.back() + counts.back()));
  }
  MPI_Gatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displ.data(), MPI_DOUBLE, 0,
              MPI_COMM_WORLD);
  return all;
}

void broadcast(std::vector<double>& values) {
  if (!many()) return;
  unsigned long long n = values.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  values.resize(n);
  MPI_Bcast(values.data(), static_cast<int>(n), MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

std::vector<std::vector<double>> all_to_all(const std::vector<std::vector<double>>& send) {
  if (!many()) return send;
  std::vector<int> scount(n_ranks), rcount(n_ranks);
  for (int q = 0; q < n_ranks; ++q) scount[q] = static_cast<int>(send[q].size());
  MPI_Alltoall(scount.data(), 1, MPI_INT, rcount.data(), 1, MPI_INT, MPI_COMM_WORLD);
  std::vector<double> sflat, rflat;
  for (const auto& s : send) sflat.insert(sflat.end(), s.begin(), s.end());
  const std::vector<int> sd = displacements(scount), rd = displacements(rcount);
  rflat.resize(static_cast<std::size_t>(rd.back() + rcount.back()));
  MPI_Alltoallv(sflat.data(), scount.data(), sd.data(), MPI_DOUBLE, rflat.data(), rcount.data(), rd.data(),
                MPI_DOUBLE, MPI_COMM_WORLD);
  std::vector<std::vector<double>> recv(n_ranks);
  for (int q = 0; q < n_ranks; ++q) recv[q].assign(rflat.begin() + rd[q], rflat.begin() + rd[q] + rcount[q]);
  return recv;
}

void exchange(const std::vector<int>& to, const std::vector<std::vector<double>>& send,
              const std::vector<int>& from, std::vector<std::vector<double>>& recv) {
  if (to.empty() && from.empty()) return;  // (also: one process, MPI never started)
  std::vector<MPI_Request> req;
  req.reserve(to.size() + from.size());
  for (std::size_t k = 0; k < from.size(); ++k) {
    req.emplace_back();
    MPI_Irecv(recv[k].data(), static_cast<int>(recv[k].size()), MPI_DOUBLE, from[k], 0, MPI_COMM_WORLD,
              &req.back());
  }
  for (std::size_t k = 0; k < to.size(); ++k) {
    req.emplace_back();
    MPI_Isend(send[k].data(), static_cast<int>(send[k].size()), MPI_DOUBLE, to[k], 0, MPI_COMM_WORLD,
              &req.back());
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
}

void abort_all(int status) {
  if (many()) MPI_Abort(MPI_COMM_WORLD, status);
}

void barrier() {
  if (many()) MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace grainlab::parallel
