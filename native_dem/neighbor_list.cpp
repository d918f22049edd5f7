// Broad phase: cell lists rebuilt into a half neighbour list with a skin, after sorting particles by
// cell so that neighbours sit close in memory. Shear history moves to the new list by stable ids.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "narrow_phase.hpp"
#include "world.hpp"

namespace grainlab::dem {

namespace {
std::uint64_t pair_key(std::int64_t a, std::int64_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) ^ static_cast<std::uint64_t>(b) ^
         (static_cast<std::uint64_t>(a) >> 32) * 0x9E3779B97F4A7C15ull;
}
struct SavedShear {
  std::uint64_t key;
  std::int64_t a, b;
  double xi;
  bool operator<(const SavedShear& o) const { return key < o.key; }
};
const SavedShear* find_saved(const std::vector<SavedShear>& saved, std::uint64_t key, std::int64_t a,
                             std::int64_t b) {
  auto it = std::lower_bound(saved.begin(), saved.end(), SavedShear{key, 0, 0, 0});
  for (; it != saved.end() && it->key == key; ++it)
    if ((it->a == a && it->b == b) || (it->a == b && it->b == a)) return &*it;
  return nullptr;
}
}  // namespace

bool World::needs_rebuild(double lookahead) const {
  if (x_build_.size() != p_.size()) return true;
  const double limit = 0.5 * skin_ - lookahead;
  if (limit <= 0) return true;
  const double limit2 = limit * limit;
  const std::size_t n = p_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = p_.x[i] - x_build_[i], dy = p_.y[i] - y_build_[i];
    if (dx * dx + dy * dy > limit2) return true;
  }
  return false;
}

void World::wrap_periodic() {
  if (period_ <= 0) return;
  for (double& x : p_.x) x -= period_ * std::floor((x - xmin_) / period_);
}

void World::rebuild_neighbors() {
  const auto started = std::chrono::steady_clock::now();
  ++diag_.neighbor_rebuilds;
  const std::size_t n = p_.size();
  // 1. Save the committed shear history by stable ids.
  std::vector<SavedShear> saved;
  if (effects_.friction) {
    for (std::size_t i = 0; i + 1 < discs_.offset.size(); ++i)
      for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k)
        if (discs_.xi[k] != 0) {
          const std::int64_t a = p_.id[i], b = p_.id[discs_.j[k]];
          saved.push_back({pair_key(a, b), a, b, discs_.xi[k]});
        }
    for (std::size_t w = 0; w < wall_lists_.size(); ++w)
      for (std::size_t k = 0; k < wall_lists_[w].particle.size(); ++k)
        if (wall_lists_[w].xi[k] != 0) {
          const std::int64_t a = p_.id[wall_lists_[w].particle[k]], b = -1 - static_cast<std::int64_t>(w);
          saved.push_back({pair_key(a, b), a, b, wall_lists_[w].xi[k]});
        }
    std::sort(saved.begin(), saved.end());
  }
  wrap_periodic();

  // 2. Cell grid over the particles' extent (wrapping in x when periodic).
  double rmax = 0, xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;
  for (std::size_t i = 0; i < n; ++i) {
    rmax = std::max(rmax, p_.r[i]);
    xlo = std::min(xlo, p_.x[i]), xhi = std::max(xhi, p_.x[i]);
    ylo = std::min(ylo, p_.y[i]), yhi = std::max(yhi, p_.y[i]);
  }
  double cell = 2 * rmax + skin_;
  if (period_ > 0) xlo = xmin_, xhi = xmin_ + period_;
  // Keep the grid no larger than a few cells per particle (a grain far from the bed must not blow it up).
  auto count_cells = [&](double c) {
    return (std::floor((xhi - xlo) / c) + 1) * (std::floor((yhi - ylo) / c) + 1);
  };
  while (n > 0 && count_cells(cell) > 4.0 * n + 64) cell *= 1.5;
  int ncx = n ? static_cast<int>(std::floor((xhi - xlo) / cell)) + 1 : 1;
  const int ncy = n ? static_cast<int>(std::floor((yhi - ylo) / cell)) + 1 : 1;
  if (period_ > 0) {
    ncx = std::max(1, static_cast<int>(std::floor(period_ / cell)));
    if (period_ < 2 * (2 * rmax + skin_))
      throw std::runtime_error("periodic_x period is shorter than two interaction ranges; make it wider");
  }
  const double cw = period_ > 0 ? period_ / ncx : cell;
  auto cell_x = [&](double x) { return std::clamp(static_cast<int>((x - xlo) / cw), 0, ncx - 1); };
  auto cell_y = [&](double y) { return std::clamp(static_cast<int>((y - ylo) / cell), 0, ncy - 1); };

  // 3. Counting sort by cell, then reorder the particle arrays (locality for the force loop).
  const std::size_t ncell = static_cast<std::size_t>(ncx) * ncy;
  std::vector<std::uint32_t> start(ncell + 1, 0), cell_of(n);
  for (std::size_t i = 0; i < n; ++i) ++start[(cell_of[i] = cell_y(p_.y[i]) * ncx + cell_x(p_.x[i])) + 1];
  for (std::size_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  order_.assign(n, 0);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) order_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }
  p_.permute(order_);

  // 4. Half list: each pair once (j > i), within the sum of radii plus the skin.
  discs_.offset.assign(n + 1, 0);
  discs_.j.clear();
  discs_.shift.clear();
  general_pairs_.clear();
  polygon_particles_.clear();
  int stencil[9];
  for (std::size_t i = 0; i < n; ++i) {
    const int cx = cell_x(p_.x[i]), cy = cell_y(p_.y[i]);
    int ns = 0;
    for (int oy = -1; oy <= 1; ++oy) {
      const int yy = cy + oy;
      if (yy < 0 || yy >= ncy) continue;
      for (int ox = -1; ox <= 1; ++ox) {
        int xx = cx + ox;
        if (period_ > 0)
          xx = (xx + ncx) % ncx;
        else if (xx < 0 || xx >= ncx)
          continue;
        const int c = yy * ncx + xx;
        if (std::find(stencil, stencil + ns, c) == stencil + ns) stencil[ns++] = c;  // narrow periodic grids
      }
    }
    const bool disc_i = p_.shape[i] < 0;
    if (!disc_i) polygon_particles_.push_back(static_cast<std::uint32_t>(i));
    for (int s = 0; s < ns; ++s)
      for (std::uint32_t j = start[stencil[s]]; j < start[stencil[s] + 1]; ++j) {
        if (j <= i) continue;
        double dx = p_.x[i] - p_.x[j];
        const double shift = period_ > 0 ? -period_ * std::round(dx / period_) : 0.0;
        dx += shift;
        const double dy = p_.y[i] - p_.y[j], reach = p_.r[i] + p_.r[j] + skin_;
        if (dx * dx + dy * dy >= reach * reach) continue;
        if (disc_i && p_.shape[j] < 0) {
          discs_.j.push_back(j);
          discs_.shift.push_back(shift);
        } else {
          general_pairs_.push_back({static_cast<std::uint32_t>(i), j, shift});
        }
      }
    discs_.offset[i + 1] = static_cast<std::uint32_t>(discs_.j.size());
  }

  // 5. Discs near each wall (walls that move are given their whole reach).
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    WallList& L = wall_lists_[w];
    L.particle.clear();
    Wall rest = walls_[w];
    rest.at(t_);
    for (std::size_t i = 0; i < n; ++i) {
      if (p_.shape[i] >= 0) continue;
      ContactGeometry c;
      if (disc_wall_contact({p_.x[i], p_.y[i]}, p_.r[i] + skin_ + 2 * rest.reach(), rest, c))
        L.particle.push_back(static_cast<std::uint32_t>(i));
    }
  }

  // 6. Restore shear history into the new slots.
  if (effects_.friction) {
    discs_.xi.assign(discs_.j.size(), 0.0);
    discs_.xi_new.assign(discs_.j.size(), 0.0);
    if (!saved.empty())
      for (std::size_t i = 0; i < n; ++i)
        for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
          const std::int64_t a = p_.id[i], b = p_.id[discs_.j[k]];
          if (const SavedShear* s = find_saved(saved, pair_key(a, b), a, b)) discs_.xi[k] = s->xi;
        }
    for (std::size_t w = 0; w < wall_lists_.size(); ++w) {
      WallList& L = wall_lists_[w];
      L.xi.assign(L.particle.size(), 0.0);
      L.xi_new.assign(L.particle.size(), 0.0);
      if (saved.empty()) continue;
      for (std::size_t k = 0; k < L.particle.size(); ++k) {
        const std::int64_t a = p_.id[L.particle[k]], b = -1 - static_cast<std::int64_t>(w);
        if (const SavedShear* s = find_saved(saved, pair_key(a, b), a, b)) L.xi[k] = s->xi;
      }
    }
  }
  x_build_ = p_.x;
  y_build_ = p_.y;
  diag_.seconds_neighbors +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

}  // namespace grainlab::dem
