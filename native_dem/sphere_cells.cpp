#include "sphere_cells.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlab::dem {

void SphereCells::build(const std::vector<Vec3>& x, double max_radius, double skin) {
  const std::size_t n = x.size();
  if (n > std::size_t{UINT32_MAX}) throw std::length_error("neighbour lists hold at most 2^32 - 1 bodies");
  ++builds_;
  skin_ = skin, reach_ = 2 * max_radius + skin, built_at_ = x;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  // Cells one reach wide, grown if a stray body would make the grid too large to hold.
  size_ = std::max(reach_, 1e-12);
  const Vec3 extent = (hi - lo).cwiseMax(Vec3::Zero());
  auto cells_along = [&](double e) { return static_cast<long>(std::floor(e / size_)) + 1; };
  while (static_cast<double>(cells_along(extent.x())) * cells_along(extent.y()) * cells_along(extent.z()) >
         4.0 * static_cast<double>(n) + 64)
    size_ *= 1.5;
  origin_ = lo, nx_ = cells_along(extent.x()), ny_ = cells_along(extent.y()), nz_ = cells_along(extent.z());
  cell_ = Vec3::Constant(size_);
  // A periodic axis: cells tile the period exactly, each at least one reach wide.
  for (int k = 0; k < 2; ++k) {
    if (period_[k] <= 0) continue;
    const long cells = static_cast<long>(std::floor(period_[k] / size_));
    if (cells < 3) throw std::invalid_argument("a periodic box must be at least three neighbour cells wide");
    origin_[k] = period_lo_[k], cell_[k] = period_[k] / static_cast<double>(cells);
    (k == 0 ? nx_ : ny_) = cells;
  }
  const std::size_t cells = static_cast<std::size_t>(nx_ * ny_ * nz_);
  coords_.resize(n);
  std::vector<std::size_t> cell_of(n);
  start_.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 r = (x[i] - origin_).cwiseQuotient(cell_);
    coords_[i] = {std::clamp(static_cast<long>(std::floor(r.x())), 0L, nx_ - 1),
                  std::clamp(static_cast<long>(std::floor(r.y())), 0L, ny_ - 1),
                  std::min(static_cast<long>(r.z()), nz_ - 1)};
    cell_of[i] = cell_index(coords_[i][0], coords_[i][1], coords_[i][2]);
    ++start_[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(n);
  std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) items_[fill[cell_of[i]]++] = i;
  // The lists: later bodies within reach in the 27 cells around, ascending.
  offset_.assign(n + 1, 0);
  list_.clear();
  const double reach2 = reach_ * reach_;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t first = list_.size();
    const auto [cx, cy, cz] = coords_[i];
    // The neighbouring cells along an axis: clamped at a free edge, wrapped on a periodic one.
    auto around = [](long c, long n, bool periodic, long out[3]) {
      int m = 0;
      for (long d = -1; d <= 1; ++d) {
        long v = c + d;
        if (periodic)
          v = (v + n) % n;
        else if (v < 0 || v >= n)
          continue;
        out[m++] = v;
      }
      return m;
    };
    long xs[3], ys[3], zs[3];
    const int mx = around(cx, nx_, period_[0] > 0, xs), my = around(cy, ny_, period_[1] > 0, ys),
              mz = around(cz, nz_, false, zs);
    for (int a = 0; a < mz; ++a)
      for (int b = 0; b < my; ++b)
        for (int e = 0; e < mx; ++e) {
          const std::size_t c = cell_index(xs[e], ys[b], zs[a]);
          for (std::size_t k = start_[c]; k < start_[c + 1]; ++k) {
            const std::size_t j = items_[k];
            if (j > i && separation(x[i], x[j]).squaredNorm() < reach2)
              list_.push_back(static_cast<Index>(j));
          }
        }
    std::sort(list_.begin() + static_cast<long>(first), list_.end());
    offset_[i + 1] = list_.size();
  }
}

bool SphereCells::stale(const std::vector<Vec3>& x) const {
  if (builds_ == 0 || x.size() != built_at_.size()) return true;
  const double limit2 = 0.25 * skin_ * skin_;
  for (std::size_t i = 0; i < x.size(); ++i)
    if ((x[i] - built_at_[i]).squaredNorm() > limit2) return true;
  return false;
}

std::size_t SphereCells::cell_index(long x, long y, long z) const {
  return static_cast<std::size_t>((z * ny_ + y) * nx_ + x);
}

}  // namespace grainlab::dem
