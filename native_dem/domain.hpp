#pragma once
// How a distributed world's plane is split into regions, one per MPI rank: a grid of px columns (cuts
// along x) by py rows (cuts along y); py = 1 gives slabs along x. Which particles each rank copies
// to the others as ghosts is kept here too. Pure bookkeeping: the World moves the data (domain.cpp).
#include <cstdint>
#include <limits>
#include <vector>

namespace grainlab::dem {

// How often `grainlab run` (and a spread bed build) re-cuts the ranks' regions by load, in steps.
inline constexpr std::uint64_t kBalanceEveryDefault = 1000;

struct Decomposition {
  bool distributed = false;
  // Move the region boundaries to even out the load every this many steps (0: never).
  std::uint64_t balance_every = 0;
  // Rows of the grid of ranks (cuts along y); the ranks must divide into them. 1: slabs along x.
  int ranks_y = 1;
  // With balancing on (balance_every > 0), every this many steps the ranks compare how fast each worked
  // through its load; if the shares that would even out their times differ by more than 5 % from the
  // present ones, the regions are re-cut to them (sphere beds; docs/parallel.md).
  std::uint64_t probe_every = 200;
};

struct Domain {
  int rank = 0, size = 1;
  int px = 1, py = 1;     // rank q is column q % px, row q / px
  bool periodic = false;  // in x
  double xmin = 0, period = 0;
  // A ghost is a particle within `halo` of a region: the largest pair reach plus the skin, so the
  // ghosts found at a rebuild cover every pair until the next one.
  double halo = 0;
  std::vector<double> xcut, ycut;  // px - 1 and py - 1 ascending boundaries
  // The share of the load each column (row) is cut to hold, summing to 1; empty: equal shares.
  std::vector<double> xshare, yshare;
  std::uint64_t next_balance_step = 0;
  // Ghost plan, fixed between rebuilds: owned indices sent to rank to[k]; counts received from from[k].
  std::vector<int> to, from;
  std::vector<std::vector<std::uint32_t>> send_index;
  std::vector<std::size_t> recv_count;
  std::vector<std::vector<double>> send_buf, recv_buf;

  // Bounds of column ix and row iy (the outer ones open, except x when periodic).
  double x_lo(int ix) const {
    if (ix > 0) return xcut[ix - 1];
    return periodic ? xmin : -std::numeric_limits<double>::infinity();
  }
  double x_hi(int ix) const {
    if (ix < px - 1) return xcut[ix];
    return periodic ? xmin + period : std::numeric_limits<double>::infinity();
  }
  double y_lo(int iy) const { return iy > 0 ? ycut[iy - 1] : -std::numeric_limits<double>::infinity(); }
  double y_hi(int iy) const { return iy < py - 1 ? ycut[iy] : std::numeric_limits<double>::infinity(); }
  // The rank owning a point (x wrapped already when periodic).
  int owner(double x, double y) const;
  // Distance from (x, y) to rank q's region (across the period when periodic).
  double distance_to_region(double x, double y, int q) const;
  // Distance from (x, y), inside this rank's region, to its nearest edge.
  double distance_to_own_edge(double x, double y) const;
  // Cuts that split points (x, y, weight, id: 4 doubles each) into px columns and py rows holding the
  // shares xshare and yshare of the weight (equal when empty); every rank computes the same cuts from the
  // same points.
  void cut_evenly(const std::vector<double>& xy_w_id);
};

// Boundaries splitting points given as (value, weight, id) triples into `size` runs of equal weight, or
// of the given shares of it (`size` of them, summing to 1); ties are broken by id, so every rank computes
// the same cuts from the same data.
std::vector<double> weighted_cuts(const std::vector<double>& vw_id, int size,
                                  const std::vector<double>& shares = {});

}  // namespace grainlab::dem
