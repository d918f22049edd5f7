// Broad phase: cell lists rebuilt into a half neighbour list with a skin, after sorting particles by
// cell so that neighbours sit close in memory. Shear history moves to the new list by stable ids. In a
// distributed world the rebuild is also when particles migrate between ranks and ghosts are renewed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "cell_grid.hpp"
#include "domain.hpp"
#include "narrow_phase.hpp"
#include "world.hpp"

namespace grainlab::dem {

std::uint64_t World::shear_key(std::int64_t a, std::int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) ^ static_cast<std::uint64_t>(b) ^
         (static_cast<std::uint64_t>(a) >> 32) * 0x9E3779B97F4A7C15ull;
}

namespace {
const World::SavedShear* find_saved(const std::vector<World::SavedShear>& saved, std::uint64_t key,
                                    std::int64_t a, std::int64_t b) {
  auto it = std::lower_bound(saved.begin(), saved.end(), World::SavedShear{key, 0, 0, 0});
  for (; it != saved.end() && it->key == key; ++it)
    if ((it->a == a && it->b == b) || (it->a == b && it->b == a)) return &*it;
  return nullptr;
}

// The shared grid (cell_grid.hpp) over the first n particles, periodic in x over [xmin, xmin + period)
// when period > 0.
CellGrid<2> disc_grid(const std::vector<double>& x, const std::vector<double>& y, std::size_t n, double reach,
                      double xmin, double period) {
  CellGrid<2> grid;
  grid.build(n,
             [&](std::size_t i) {
               return std::array<double, 2>{x[i], y[i]};
             },
             reach, {period, 0.0}, {xmin, 0.0});
  return grid;
}
}  // namespace

bool World::needs_rebuild(double lookahead) const {
  bool mine = x_build_.size() != n_own_;
  const double limit = 0.5 * skin_ - lookahead;
  if (limit <= 0) mine = true;
  const double limit2 = limit * limit;
  for (std::size_t i = 0; i < n_own_ && !mine; ++i) {
    const double dx = p_.x[i] - x_build_[i], dy = p_.y[i] - y_build_[i];
    if (dx * dx + dy * dy > limit2) mine = true;
  }
  return any_rank(mine);
}

void World::wrap_periodic() {
  if (period_ <= 0) return;
  for (std::size_t i = 0; i < n_own_; ++i) p_.x[i] -= period_ * std::floor((p_.x[i] - xmin_) / period_);
}

std::vector<World::SavedShear> World::save_history() const {
  std::vector<SavedShear> saved;
  if (!effects_.has(Effect::friction)) return saved;
  for (std::size_t i = 0; i + 1 < discs_.offset.size(); ++i)
    for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k)
      if (discs_.xi[k] != 0) {
        const std::int64_t a = p_.id[i], b = p_.id[discs_.j[k]];
        saved.push_back({World::shear_key(a, b), a, b, discs_.xi[k]});
      }
  for (std::size_t w = 0; w < wall_lists_.size(); ++w)
    for (std::size_t k = 0; k < wall_lists_[w].particle.size(); ++k)
      if (wall_lists_[w].xi[k] != 0) {
        const std::int64_t a = p_.id[wall_lists_[w].particle[k]], b = -1 - static_cast<std::int64_t>(w);
        saved.push_back({World::shear_key(a, b), a, b, wall_lists_[w].xi[k]});
      }
  return saved;
}

void World::rebuild_neighbors() {
  const auto started = std::chrono::steady_clock::now();
  ++diag_.neighbor_rebuilds;
  extra_reach_ = 0;
  std::vector<SavedShear> saved = save_history();
  p_.resize(n_own_);  // ghosts are renewed below
  wrap_periodic();
  if (domain_) {
    if (decomposition_.balance_every > 0 && diag_.steps >= domain_->next_balance_step) balance_regions();
    migrate(saved);
  }
  std::sort(saved.begin(), saved.end());
  sort_owned_by_cell();
  if (domain_) receive_ghosts();
  build_pair_lists();
  build_incidence();
  restore_history(saved);
  x_build_.assign(p_.x.begin(), p_.x.begin() + static_cast<long>(n_own_));
  y_build_.assign(p_.y.begin(), p_.y.begin() + static_cast<long>(n_own_));
  load_.owned = n_own_;
  load_.ghosts = p_.size() - n_own_;
  load_.pairs = discs_.j.size();
  diag_.seconds_neighbors +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

// Counting sort of the owned particles by cell: neighbours end up close in memory.
void World::sort_owned_by_cell() {
  double rmax = 0;
  for (std::size_t i = 0; i < n_own_; ++i) rmax = std::max(rmax, p_.r[i]);
  check_period(rmax);
  const CellGrid<2> grid = disc_grid(p_.x, p_.y, n_own_, 2 * rmax + skin_, xmin_, period_);
  order_ = grid.members();
  p_.permute(order_);
}

// Half list over owned particles and ghosts (never two ghosts): each pair once, within the sum of
// radii plus the skin, in the row of its lower-id particle.
void World::build_pair_lists() {
  const std::size_t n = p_.size();
  double rmax = 0;
  for (std::size_t i = 0; i < n; ++i) rmax = std::max(rmax, p_.r[i]);
  const CellGrid<2> grid = disc_grid(p_.x, p_.y, n, 2 * rmax + skin_ + extra_reach_, xmin_, period_);
  const std::vector<std::uint32_t>&start = grid.start(), &members = grid.members();
  struct Found {
    std::uint32_t a, b;
    double shift;
  };
  std::vector<Found> found;
  general_pairs_.clear();
  polygon_particles_.clear();
  std::size_t stencil[9];
  for (std::size_t i = 0; i < n; ++i) {
    const bool disc_i = p_.shape[i] < 0, ghost_i = i >= n_own_;
    if (!disc_i && !ghost_i) polygon_particles_.push_back(static_cast<std::uint32_t>(i));
    const int ns = grid.stencil(grid.coords({p_.x[i], p_.y[i]}), stencil);
    for (int s = 0; s < ns; ++s)
      for (std::uint32_t m = start[stencil[s]]; m < start[stencil[s] + 1]; ++m) {
        const std::uint32_t j = members[m];
        if (j <= i || (ghost_i && j >= n_own_)) continue;
        // Orient by id: the same pair gives the same bits on every rank.
        const bool swap = p_.id[j] < p_.id[i];
        const std::uint32_t a = swap ? j : static_cast<std::uint32_t>(i),
                            b = swap ? static_cast<std::uint32_t>(i) : j;
        double dx = p_.x[a] - p_.x[b];
        const double shift = period_ > 0 ? -period_ * std::round(dx / period_) : 0.0;
        dx += shift;
        const double dy = p_.y[a] - p_.y[b], reach = p_.r[a] + p_.r[b] + skin_ + extra_reach_;
        if (dx * dx + dy * dy >= reach * reach) continue;
        if (disc_i && p_.shape[j] < 0)
          found.push_back({a, b, shift});
        else
          general_pairs_.push_back({a, b, shift});
      }
  }
  discs_.offset.assign(n + 1, 0);
  for (const Found& f : found) ++discs_.offset[f.a + 1];
  for (std::size_t i = 0; i < n; ++i) discs_.offset[i + 1] += discs_.offset[i];
  discs_.j.resize(found.size());
  discs_.shift.resize(found.size());
  std::vector<std::uint32_t> fill(discs_.offset.begin(), discs_.offset.end() - 1);
  for (const Found& f : found) {
    const std::uint32_t k = fill[f.a]++;
    discs_.j[k] = f.b;
    discs_.shift[k] = f.shift;
  }
  discs_.force.assign(3 * found.size(), 0.0);
  discs_.touching.assign(found.size(), 0);

  // Discs near each wall (walls that move are given their whole reach); owned discs only.
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    WallList& L = wall_lists_[w];
    L.particle.clear();
    Wall rest = walls_[w];
    rest.at(t_);
    for (std::size_t i = 0; i < n_own_; ++i) {
      if (p_.shape[i] >= 0) continue;
      ContactGeometry c;
      if (disc_wall_contact({p_.x[i], p_.y[i]}, p_.r[i] + skin_ + extra_reach_ + 2 * rest.reach(), rest, c))
        L.particle.push_back(static_cast<std::uint32_t>(i));
    }
  }
}

// For every owned particle, its pairs sorted by partner id: the order its forces are summed in.
void World::build_incidence() {
  std::vector<std::uint32_t>& io = discs_.inc_offset;
  io.assign(n_own_ + 1, 0);
  const std::size_t rows = discs_.offset.size() - 1;
  for (std::size_t i = 0; i < rows; ++i)
    for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
      if (i < n_own_) ++io[i + 1];
      if (discs_.j[k] < n_own_) ++io[discs_.j[k] + 1];
    }
  for (std::size_t i = 0; i < n_own_; ++i) io[i + 1] += io[i];
  std::vector<std::pair<std::int64_t, std::uint32_t>> entries(io[n_own_]);
  std::vector<std::uint32_t> fill(io.begin(), io.end() - 1);
  for (std::size_t i = 0; i < rows; ++i)
    for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
      const std::uint32_t j = discs_.j[k];
      if (i < n_own_) entries[fill[i]++] = {p_.id[j], 2 * k};
      if (j < n_own_) entries[fill[j]++] = {p_.id[i], 2 * k + 1};
    }
  discs_.inc.resize(entries.size());
  for (std::size_t i = 0; i < n_own_; ++i) {
    std::sort(entries.begin() + io[i], entries.begin() + io[i + 1]);
    for (std::uint32_t e = io[i]; e < io[i + 1]; ++e) discs_.inc[e] = entries[e].second;
  }
}

void World::restore_history(std::vector<SavedShear>& saved) {
  if (!effects_.has(Effect::friction)) return;
  discs_.xi.assign(discs_.j.size(), 0.0);
  discs_.xi_new.assign(discs_.j.size(), 0.0);
  if (!saved.empty())
    for (std::size_t i = 0; i + 1 < discs_.offset.size(); ++i)
      for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
        const std::int64_t a = p_.id[i], b = p_.id[discs_.j[k]];
        if (const SavedShear* s = find_saved(saved, World::shear_key(a, b), a, b)) discs_.xi[k] = s->xi;
      }
  for (std::size_t w = 0; w < wall_lists_.size(); ++w) {
    WallList& L = wall_lists_[w];
    L.xi.assign(L.particle.size(), 0.0);
    L.xi_new.assign(L.particle.size(), 0.0);
    if (saved.empty()) continue;
    for (std::size_t k = 0; k < L.particle.size(); ++k) {
      const std::int64_t a = p_.id[L.particle[k]], b = -1 - static_cast<std::int64_t>(w);
      if (const SavedShear* s = find_saved(saved, World::shear_key(a, b), a, b)) L.xi[k] = s->xi;
    }
  }
}

}  // namespace grainlab::dem
