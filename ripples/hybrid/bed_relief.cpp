#include "bed_relief.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unsupported/Eigen/FFT>

namespace grainlab::ripples::hybrid {

namespace {
// Heights of the layers above the bed, d: doubling from half a diameter, up past the saltation layer.
constexpr std::array<double, 10> kLayers = {0.5, 1, 2, 4, 8, 16, 32, 64, 128, 256};

// A signed frequency index: 0, 1, ..., n/2, then the negative ones.
double wavenumber(std::size_t m, std::size_t n, double period) {
  const double k = m <= n / 2 ? static_cast<double>(m) : static_cast<double>(m) - static_cast<double>(n);
  return 2 * std::numbers::pi * k / period;
}

// The 2-D transform of a grid (x fastest), forward or inverse (scaled), as 1-D transforms of its rows
// and then of its columns.
void transform(std::vector<std::complex<double>>& a, std::size_t nx, std::size_t ny, bool forward) {
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> in, out;
  in.resize(nx);
  for (std::size_t j = 0; j < ny; ++j) {
    std::copy_n(a.begin() + static_cast<long>(j * nx), nx, in.begin());
    forward ? fft.fwd(out, in) : fft.inv(out, in);
    std::copy_n(out.begin(), nx, a.begin() + static_cast<long>(j * nx));
  }
  in.resize(ny);
  for (std::size_t i = 0; i < nx; ++i) {
    for (std::size_t j = 0; j < ny; ++j) in[j] = a[j * nx + i];
    forward ? fft.fwd(out, in) : fft.inv(out, in);
    for (std::size_t j = 0; j < ny; ++j) a[j * nx + i] = out[j];
  }
}
}  // namespace

BedRelief::BedRelief(std::size_t nx, std::size_t ny, double cell, double d)
    : nx_(nx), ny_(ny), cell_(cell), inv_cell_(1 / cell) {
  if (nx < 2 || ny < 2 || !(cell > 0) || !(d > 0)) throw std::invalid_argument("BedRelief: an empty grid");
  for (double z : kLayers) z_.push_back(z * d);
  values_.assign(nx * ny * z_.size(), 0.0);
}

void BedRelief::refresh(const std::vector<double>& heights, double mean) {
  if (heights.size() != nx_ * ny_) throw std::invalid_argument("BedRelief: heights of another grid");
  modes_.resize(heights.size());
  for (std::size_t k = 0; k < heights.size(); ++k) modes_[k] = heights[k] - mean;
  transform(modes_, nx_, ny_, true);
  const double length = static_cast<double>(nx_) * cell_, width = static_cast<double>(ny_) * cell_;
  std::vector<double> k_abs(modes_.size());
  for (std::size_t j = 0; j < ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i)
      k_abs[j * nx_ + i] = std::hypot(wavenumber(i, nx_, length), wavenumber(j, ny_, width));
  std::vector<std::complex<double>> faded(modes_.size());
  for (std::size_t l = 0; l < z_.size(); ++l) {
    for (std::size_t k = 0; k < modes_.size(); ++k) faded[k] = modes_[k] * std::exp(-k_abs[k] * z_[l]);
    transform(faded, nx_, ny_, false);
    for (std::size_t k = 0; k < faded.size(); ++k) values_[k * z_.size() + l] = faded[k].real();
  }
}

// Layers l and l + 1 at (x, y), bilinear between the key points around it.
std::array<double, 2> BedRelief::pair_at(std::size_t l, double x, double y) const {
  const double sx = x * inv_cell_, sy = y * inv_cell_;
  auto i0 = static_cast<std::size_t>(sx), j0 = static_cast<std::size_t>(sy);
  const double fx = sx - static_cast<double>(i0), fy = sy - static_cast<double>(j0);
  i0 = std::min(i0, nx_ - 1), j0 = std::min(j0, ny_ - 1);
  const std::size_t i1 = i0 + 1 == nx_ ? 0 : i0 + 1, j1 = j0 + 1 == ny_ ? 0 : j0 + 1;
  const std::size_t n = z_.size();
  const double *p00 = &values_[(j0 * nx_ + i0) * n + l], *p10 = &values_[(j0 * nx_ + i1) * n + l],
               *p01 = &values_[(j1 * nx_ + i0) * n + l], *p11 = &values_[(j1 * nx_ + i1) * n + l];
  std::array<double, 2> out{};
  for (std::size_t k = 0; k < 2 && l + k < n; ++k) {
    const double lo = p00[k] + fx * (p10[k] - p00[k]), hi = p01[k] + fx * (p11[k] - p01[k]);
    out[k] = lo + fy * (hi - lo);
  }
  return out;
}

double BedRelief::at(double x, double y, double s, double relief_at_bed) const {
  s = std::max(s, 0.0);
  const std::size_t top = z_.size() - 1;
  if (s < z_.front()) return relief_at_bed + s / z_.front() * (pair_at(0, x, y)[0] - relief_at_bed);
  if (s >= z_[top]) return s >= 2 * z_[top] ? 0 : pair_at(top, x, y)[0] * (2 - s / z_[top]);
  // The layers double in height: s / z_0 = m 2^e with m in [0.5, 1) lies between layers e - 1 and e.
  int e = 0;
  std::frexp(s / z_.front(), &e);
  std::size_t l = std::min(static_cast<std::size_t>(e - 1), top - 1);
  if (s < z_[l]) --l;  // (s / z_0 rounded up onto a layer's height)
  const auto [a, b] = pair_at(l, x, y);
  return a + (s - z_[l]) / (z_[l + 1] - z_[l]) * (b - a);
}

const std::vector<double>& BedRelief::layer(std::size_t l) const {
  column_.resize(nx_ * ny_);
  for (std::size_t k = 0; k < column_.size(); ++k) column_[k] = values_[k * z_.size() + l];
  return column_;
}

}  // namespace grainlab::ripples::hybrid
