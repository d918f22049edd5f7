#include "airborne.hpp"

#include <algorithm>
#include <cmath>

namespace grainlab::ripples::hybrid {

namespace {
long wrap(long i, long n) {
  return i < 0 ? i + n : (i >= n ? i - n : i);
}
// The nearest periodic image of a separation (both grains inside the box).
double nearest(double s, double period) {
  return s > 0.5 * period ? s - period : (s < -0.5 * period ? s + period : s);
}
}  // namespace

CollisionGrid::CollisionGrid(double length, double width, double d)
    : nx_(std::max(3L, static_cast<long>(length / d))),
      ny_(std::max(3L, static_cast<long>(width / d))),
      inv_hx_(static_cast<double>(nx_) / length),
      inv_hy_(static_cast<double>(ny_) / width),
      d_(d),
      length_(length),
      width_(width) {}

void CollisionGrid::set_sizes(std::vector<double> diameters, std::vector<double> masses) {
  diameters_ = std::move(diameters), masses_ = std::move(masses);
}

std::uint64_t CollisionGrid::collide_all(Grains& g, double m, const CollisionLaw& law) {
  return diameters_.empty() ? collide_as<false>(g, m, law) : collide_as<true>(g, m, law);
}

// Once per bed (one size or several), so grains of one size pay nothing for the size lookup.
template <bool kMixed>
std::uint64_t CollisionGrid::collide_as(Grains& g, double m, const CollisionLaw& law) {
  const std::size_t n = g.size();
  if (head_.empty()) head_.assign(static_cast<std::size_t>(nx_ * ny_), kNone);
  next_.resize(n), column_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const long ix = std::min(nx_ - 1, static_cast<long>(g.x[i] * inv_hx_));
    const long iy = std::min(ny_ - 1, static_cast<long>(g.y[i] * inv_hy_));
    const auto c = static_cast<std::uint32_t>(ix * ny_ + iy);
    column_[i] = c, next_[i] = head_[c], head_[c] = i;
  }
  std::uint64_t hits = 0;
  static constexpr long kAhead[4][2] = {{1, -1}, {1, 0}, {1, 1}, {0, 1}};
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = next_[i]; j != kNone; j = next_[j]) hits += pair<kMixed>(g, i, j, m, law);
    const long ix = static_cast<long>(column_[i]) / ny_, iy = static_cast<long>(column_[i]) % ny_;
    for (const auto& off : kAhead) {
      const auto o = static_cast<std::size_t>(wrap(ix + off[0], nx_) * ny_ + wrap(iy + off[1], ny_));
      for (std::uint32_t j = head_[o]; j != kNone; j = next_[j]) hits += pair<kMixed>(g, i, j, m, law);
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) head_[column_[i]] = kNone;
  return hits;
}

template <bool kMixed>
bool CollisionGrid::pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) const {
  const double dz = g.z[j] - g.z[i];
  if (dz >= d_ || dz <= -d_) return false;
  const double dx = nearest(g.x[j] - g.x[i], length_), dy = nearest(g.y[j] - g.y[i], width_);
  const double r2 = dx * dx + dy * dy + dz * dz;
  double reach = d_, mi = m, mj = m;
  if constexpr (kMixed) {
    const std::size_t ki = g.kind[i], kj = g.kind[j];
    reach = 0.5 * (diameters_[ki] + diameters_[kj]), mi = masses_[ki], mj = masses_[kj];
  }
  if (r2 >= reach * reach || r2 <= 0) return false;
  Vec3 v1{g.vx[i], g.vy[i], g.vz[i]}, v2{g.vx[j], g.vy[j], g.vz[j]};
  if (!collide(v1, v2, mi, mj, Vec3{dx, dy, dz} / std::sqrt(r2), law)) return false;
  g.vx[i] = v1.x(), g.vy[i] = v1.y(), g.vz[i] = v1.z(), g.vx[j] = v2.x(), g.vy[j] = v2.y(), g.vz[j] = v2.z();
  return true;
}

}  // namespace grainlab::ripples::hybrid
