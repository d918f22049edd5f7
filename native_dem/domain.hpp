#pragma once
// How a distributed world's x axis is split into slabs, one per MPI rank, and which particles each
// rank copies to its neighbours as ghosts. Pure bookkeeping: the World moves the data (domain.cpp).
#include <cstdint>
#include <limits>
#include <vector>

namespace grainlab::dem {

struct Domain {
  int rank = 0, size = 1;
  bool periodic = false;
  double xmin = 0, period = 0;
  // A ghost is a particle within `halo` of a slab: the largest pair reach plus the skin, so the ghosts
  // found at a rebuild cover every pair until the next one.
  double halo = 0;
  std::vector<double> cut;  // size - 1 ascending boundaries; rank q owns [cut[q - 1], cut[q])
  std::uint64_t next_balance_step = 0;
  // Ghost plan, fixed between rebuilds: owned indices sent to rank to[k]; counts received from from[k].
  std::vector<int> to, from;
  std::vector<std::vector<std::uint32_t>> send_index;
  std::vector<std::size_t> recv_count;
  std::vector<std::vector<double>> send_buf, recv_buf;

  double lo(int q) const {
    if (q > 0) return cut[q - 1];
    return periodic ? xmin : -std::numeric_limits<double>::infinity();
  }
  double hi(int q) const {
    if (q < size - 1) return cut[q];
    return periodic ? xmin + period : std::numeric_limits<double>::infinity();
  }
  // The rank owning a (wrapped) x.
  int owner(double x) const;
  // Distance from x to rank q's slab (across the period when periodic).
  double distance_to_slab(double x, int q) const;
};

// Boundaries splitting points given as (x, weight, id) triples into `size` runs of equal weight; ties
// in x are broken by id, so every rank computes the same cuts from the same data.
std::vector<double> weighted_cuts(const std::vector<double>& xw_id, int size);

}  // namespace grainlab::dem
