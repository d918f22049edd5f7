#pragma once
// The bed's relief as the wind above it feels it. Over a low, periodic bed, potential flow lifts its
// streamlines by each Fourier mode of the relief (the bed less its mean level) times exp(-|k| s) at a
// height s above the bed: short waves are felt only near the bed, long ones higher up. The wind column
// then stands, at height s, on the bed's relief as it has faded there (the column on the mean level and
// the column on the bed beneath each grain are the limits k -> infinity and k -> 0). Computed once per
// wind update on a few heights (an FFT of the key points' grid) and read per grain by interpolation.
#include <algorithm>
#include <array>
#include <bit>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "height_field.hpp"

namespace grainlab::ripples::hybrid {

class BedRelief {
 public:
  // On the key points of `grid` (which must outlive this); heights of the layers are in units of d (cm).
  BedRelief(const HeightField& grid, double d);
  // The relief of `heights` (x fastest, as HeightField's) about `mean`, at every layer's height.
  void refresh(const std::vector<double>& heights, double mean);
  // The relief felt at (x, y) (inside the box), s >= 0 above the bed (cm), given the bed's own relief
  // there (at s = 0, where the surface is followed exactly): linear in s between the layers, bilinear
  // between key points, fading to zero over the top layer's height above it.
  double at(double x, double y, double s, double relief_at_bed) const;
  // The layers' heights above the bed (cm) and a copy of a layer's values (x fastest): for tests and plots.
  const std::vector<double>& heights() const { return z_; }
  std::vector<double> layer(std::size_t l) const;

 private:
  // Layer l at (x, y) and, unless it is the top one, layer l + 1: bilinear between the key points.
  template <bool kBoth>
  std::array<double, 2> pair_at(std::size_t l, double x, double y) const;
  const HeightField& grid_;
  std::size_t nx_, ny_;
  double inv_z0_ = 0;
  std::vector<double> k_abs_;    // |k| of each mode of the grid's transform, 1/cm
  std::vector<double> inv_gap_;  // 1 / (z_[l + 1] - z_[l])
  std::vector<double> z_;        // above the bed, cm, ascending (the first > 0)
  // Per key point (x fastest), the faded relief at every height in turn: a grain reads two heights at
  // four key points, 16 bytes at each.
  std::vector<double> values_;
};

// Inline: every airborne grain reads the relief twice a step.
template <bool kBoth>
inline std::array<double, 2> BedRelief::pair_at(std::size_t l, double x, double y) const {
  const auto [i0, j0, fx, fy] = grid_.place(x, y);  // (the bed's own cells, wrapped as it wraps them)
  const std::size_t i1 = i0 + 1 == nx_ ? 0 : i0 + 1, j1 = j0 + 1 == ny_ ? 0 : j0 + 1;
  const std::size_t n = z_.size();
  const double *p00 = &values_[(j0 * nx_ + i0) * n + l], *p10 = &values_[(j0 * nx_ + i1) * n + l],
               *p01 = &values_[(j1 * nx_ + i0) * n + l], *p11 = &values_[(j1 * nx_ + i1) * n + l];
  std::array<double, 2> out{};
  for (std::size_t k = 0; k < (kBoth ? 2u : 1u); ++k) {
    const double lo = p00[k] + fx * (p10[k] - p00[k]), hi = p01[k] + fx * (p11[k] - p01[k]);
    out[k] = lo + fy * (hi - lo);
  }
  return out;
}

inline double BedRelief::at(double x, double y, double s, double relief_at_bed) const {
  s = std::max(s, 0.0);
  const std::size_t top = z_.size() - 1;
  if (s < z_.front()) return relief_at_bed + s * inv_z0_ * (pair_at<false>(0, x, y)[0] - relief_at_bed);
  if (s >= z_[top]) return s >= 2 * z_[top] ? 0 : pair_at<false>(top, x, y)[0] * (2 - s / z_[top]);
  // The layers double in height, so s / z_0's binary exponent names the layer below s (corrected by one
  // where rounding put s / z_0 across a power of two).
  const auto bits = std::bit_cast<std::uint64_t>(s * inv_z0_);
  const int exponent = static_cast<int>(bits >> 52 & 0x7ff) - 1023;
  std::size_t l = static_cast<std::size_t>(std::clamp(exponent, 0, static_cast<int>(top) - 1));
  if (s < z_[l])
    --l;
  else if (l + 1 < top && s >= z_[l + 1])
    ++l;
  const auto [a, b] = pair_at<true>(l, x, y);
  return a + (s - z_[l]) * inv_gap_[l] * (b - a);
}

}  // namespace grainlab::ripples::hybrid
