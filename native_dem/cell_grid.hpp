#pragma once
// The neighbour machinery both engines build their lists from: a uniform grid of cells over points in D
// dimensions (2: discs, 3: spheres). Cells are at least `reach` wide, grown when the grid would hold more
// than 4 n + 64 cells (a stray body far from the bed must not blow it up); a periodic axis is tiled
// exactly by whole cells; points are bucketed by a counting sort, in index order within a cell. The 2-D
// engine's pair lists (neighbor_list.cpp) and the 3-D engine's Verlet lists (sphere_cells.cpp) are both
// built on it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace grainlab::dem {

template <int D>
class CellGrid {
 public:
  using Point = std::array<double, D>;
  using Coords = std::array<long, D>;

  // point(i) gives point i's coordinates. period[k] > 0 makes axis k periodic over
  // [period_lo[k], period_lo[k] + period[k]) (the points must lie inside it).
  template <class PointOf>
  void build(std::size_t n, PointOf point, double reach, const Point& period = {},
             const Point& period_lo = {}) {
    Point lo, hi;
    lo.fill(1e300), hi.fill(-1e300);
    for (std::size_t i = 0; i < n; ++i) {
      const Point p = point(i);
      for (int k = 0; k < D; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
    }
    for (int k = 0; k < D; ++k) {
      periodic_[k] = period[k] > 0;
      if (periodic_[k]) lo[k] = period_lo[k], hi[k] = period_lo[k] + period[k];
      if (n == 0) lo[k] = hi[k] = 0;
    }
    double cell = std::max(reach, 1e-12);
    auto count = [&](double c) {
      double cells = 1;
      for (int k = 0; k < D; ++k) cells *= std::floor((hi[k] - lo[k]) / c) + 1;
      return cells;
    };
    while (n > 0 && count(cell) > 4.0 * static_cast<double>(n) + 64) cell *= 1.5;
    std::size_t total = 1;
    for (int k = 0; k < D; ++k) {
      lo_[k] = lo[k];
      cells_[k] = static_cast<long>(std::floor((hi[k] - lo[k]) / cell)) + 1;
      size_[k] = cell;
      if (periodic_[k]) {  // whole cells, each at least one reach wide
        cells_[k] = std::max(1L, static_cast<long>(std::floor(period[k] / cell)));
        size_[k] = period[k] / static_cast<double>(cells_[k]);
      }
      total *= static_cast<std::size_t>(cells_[k]);
    }
    start_.assign(total + 1, 0);
    std::vector<std::uint32_t> cell_of(n);
    for (std::size_t i = 0; i < n; ++i)
      ++start_[(cell_of[i] = static_cast<std::uint32_t>(index(coords(point(i))))) + 1];
    for (std::size_t c = 0; c < total; ++c) start_[c + 1] += start_[c];
    members_.assign(n, 0);
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }

  Coords coords(const Point& p) const {
    Coords c;
    for (int k = 0; k < D; ++k)
      c[k] = std::clamp(static_cast<long>(std::floor((p[k] - lo_[k]) / size_[k])), 0L, cells_[k] - 1);
    return c;
  }
  std::size_t index(const Coords& c) const {
    std::size_t at = 0;
    for (int k = D - 1; k >= 0; --k)
      at = at * static_cast<std::size_t>(cells_[k]) + static_cast<std::size_t>(c[k]);
    return at;
  }
  // The distinct cells around c, itself included (clamped at a free edge, wrapped on a periodic axis; a
  // periodic axis of one or two cells lists each only once). Writes at most 3^D indices; returns how many.
  int stencil(const Coords& c, std::size_t* out) const {
    long along[D][3];
    int m[D];
    for (int k = 0; k < D; ++k) {
      m[k] = 0;
      for (long d = -1; d <= 1; ++d) {
        long v = c[k] + d;
        if (periodic_[k])
          v = ((v % cells_[k]) + cells_[k]) % cells_[k];
        else if (v < 0 || v >= cells_[k])
          continue;
        if (std::find(along[k], along[k] + m[k], v) == along[k] + m[k]) along[k][m[k]++] = v;
      }
    }
    int ns = 0;
    Coords at;
    auto visit = [&](auto& self, int k) -> void {
      if (k < 0) {
        out[ns++] = index(at);
        return;
      }
      for (int a = 0; a < m[k]; ++a) at[k] = along[k][a], self(self, k - 1);
    };
    visit(visit, D - 1);
    return ns;
  }
  // The points in cell c: members()[start()[c] .. start()[c + 1]), ascending.
  const std::vector<std::uint32_t>& members() const { return members_; }
  const std::vector<std::uint32_t>& start() const { return start_; }
  const std::array<double, D>& cell_size() const { return size_; }
  const std::array<long, D>& cells() const { return cells_; }

 private:
  std::array<double, D> lo_{}, size_{};
  std::array<long, D> cells_{};
  std::array<bool, D> periodic_{};
  std::vector<std::uint32_t> start_, members_;
};

}  // namespace grainlab::dem
