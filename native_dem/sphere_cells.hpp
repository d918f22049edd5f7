#pragma once
// The 3-D engine's broad phase: a Verlet list. Bounding spheres are binned in a grid of cells one largest
// diameter plus a skin wide (cell_grid.hpp, shared with 2-D); each body keeps the later bodies (in index
// order) within that reach, sorted. A force loop over them visits the overlapping pairs in exactly the
// all-pairs order (the same sums, bit for bit) in O(N). The lists stay valid until some body has moved half
// the skin since they were built.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cell_grid.hpp"
#include "polyhedron.hpp"

namespace grainlab::dem {

class SphereCells {
 public:
  // A periodic axis must hold at least this many cells (each one list reach wide).
  static constexpr int kMinPeriodicCells = 3;
  // Makes axis 0 (x) or 1 (y) periodic over [lo, hi): cells wrap and distances take the nearest image.
  // Bodies must be inside [lo, hi) when the lists are built, and the period must hold three cells.
  void set_period(int axis, double lo, double hi) { period_[axis] = hi - lo, period_lo_[axis] = lo; }
  // The separation a - b, through the nearest periodic image.
  Vec3 separation(const Vec3& a, const Vec3& b) const {
    Vec3 d = a - b;
    for (int k = 0; k < 2; ++k)
      if (period_[k] > 0) d[k] -= period_[k] * std::round(d[k] / period_[k]);
    return d;
  }
  // The same for a separation already taken (x and y components).
  void to_nearest_image(double& dx, double& dy) const {
    if (period_[0] > 0) dx -= period_[0] * std::round(dx / period_[0]);
    if (period_[1] > 0) dy -= period_[1] * std::round(dy / period_[1]);
  }
  // Builds the lists for bodies at `centres` whose bounding radii are at most `max_radius`. `held` (one
  // flag per body, or nullptr): two bodies both flagged (held in place) are not listed as a pair.
  void build(const std::vector<Vec3>& centres, double max_radius, double skin = 0,
             const std::uint8_t* held = nullptr);
  // True if the lists must be rebuilt for these positions (never built, another count, or a body moved
  // more than half the skin).
  bool stale(const std::vector<Vec3>& centres) const;
  // The indices j > i within reach of i, ascending (32 bits: the lists are walked every step).
  using Index = std::uint32_t;
  const Index* begin(std::size_t i) const { return list_.data() + offset_[i]; }
  const Index* end(std::size_t i) const { return list_.data() + offset_[i + 1]; }
  // Where i's entries start in the concatenated lists (per-entry data sits at the same positions).
  std::size_t first(std::size_t i) const { return offset_[i]; }
  std::size_t entries() const { return list_.size(); }
  // first(i) for every i, and the end (32 bits too: the sweep reads two a sphere every step)
  const Index* offsets() const { return offset_.data(); }
  std::size_t builds() const { return builds_; }
  // Where the centres were at the last build.
  const std::vector<Vec3>& build_positions() const { return built_at_; }

 private:
  CellGrid<3> grid_;
  double skin_ = 0, reach_ = 0;
  std::vector<Vec3> built_at_;
  std::vector<Index> offset_;
  std::vector<Index> list_;
  std::size_t builds_ = 0;
  double period_[2] = {0, 0}, period_lo_[2] = {0, 0};
};

}  // namespace grainlab::dem
