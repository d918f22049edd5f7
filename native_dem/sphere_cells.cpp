#include "sphere_cells.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace grainlab::dem {

void SphereCells::build(const std::vector<Vec3>& x, double max_radius, double skin,
                        const std::uint8_t* held) {
  const std::size_t n = x.size();
  if (n > std::size_t{UINT32_MAX}) throw std::length_error("neighbour lists hold at most 2^32 - 1 bodies");
  ++builds_;
  skin_ = skin, reach_ = 2 * max_radius + skin, built_at_ = x;
  auto point = [&](std::size_t i) { return std::array<double, 3>{x[i].x(), x[i].y(), x[i].z()}; };
  grid_.build(n, point, reach_, {period_[0], period_[1], 0.0}, {period_lo_[0], period_lo_[1], 0.0});
  for (int k = 0; k < 2; ++k)
    if (period_[k] > 0 && grid_.cells()[k] < kMinPeriodicCells)
      throw std::invalid_argument("a periodic box must be at least three neighbour cells wide");
  // The lists: later bodies within reach in the cells around, ascending.
  offset_.assign(n + 1, 0);
  list_.clear();
  const double reach2 = reach_ * reach_;
  const std::vector<std::uint32_t>& start = grid_.start();
  const std::vector<std::uint32_t>& members = grid_.members();
  std::size_t around[27];
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t first = list_.size();
    const int ns = grid_.stencil(grid_.coords(point(i)), around);
    for (int s = 0; s < ns; ++s)
      for (std::uint32_t m = start[around[s]]; m < start[around[s] + 1]; ++m) {
        const std::size_t j = members[m];
        if (j > i && separation(x[i], x[j]).squaredNorm() < reach2 && !(held && held[i] && held[j]))
          list_.push_back(static_cast<Index>(j));
      }
    std::sort(list_.begin() + static_cast<long>(first), list_.end());
    if (list_.size() > std::numeric_limits<Index>::max())
      throw std::length_error("neighbour lists longer than 2^32 entries");
    offset_[i + 1] = static_cast<Index>(list_.size());
  }
}

bool SphereCells::stale(const std::vector<Vec3>& x) const {
  if (builds_ == 0 || x.size() != built_at_.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < x.size(); ++i)
    if ((x[i] - built_at_[i]).squaredNorm() > limit2) return true;
  return false;
}

}  // namespace grainlab::dem
