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

BedRelief::BedRelief(const HeightField& grid, double d) : grid_(grid), nx_(grid.nx()), ny_(grid.ny()) {
  if (nx_ < 2 || ny_ < 2 || !(d > 0)) throw std::invalid_argument("BedRelief: an empty grid");
  for (double z : kLayers) z_.push_back(z * d);
  inv_z0_ = 1 / z_.front();
  for (std::size_t l = 0; l + 1 < z_.size(); ++l) inv_gap_.push_back(1 / (z_[l + 1] - z_[l]));
  values_.assign(nx_ * ny_ * z_.size(), 0.0);
  const double length = static_cast<double>(nx_) * grid.cell(),
               width = static_cast<double>(ny_) * grid.cell();
  k_abs_.resize(nx_ * ny_);
  for (std::size_t j = 0; j < ny_; ++j)
    for (std::size_t i = 0; i < nx_; ++i)
      k_abs_[j * nx_ + i] = std::hypot(wavenumber(i, nx_, length), wavenumber(j, ny_, width));
}

void BedRelief::refresh(const std::vector<double>& heights, double mean) {
  if (heights.size() != nx_ * ny_) throw std::invalid_argument("BedRelief: heights of another grid");
  std::vector<std::complex<double>> modes(heights.size()), faded(heights.size());
  for (std::size_t k = 0; k < heights.size(); ++k) modes[k] = heights[k] - mean;
  transform(modes, nx_, ny_, true);
  for (std::size_t l = 0; l < z_.size(); ++l) {
    for (std::size_t k = 0; k < modes.size(); ++k) faded[k] = modes[k] * std::exp(-k_abs_[k] * z_[l]);
    transform(faded, nx_, ny_, false);
    for (std::size_t k = 0; k < faded.size(); ++k) values_[k * z_.size() + l] = faded[k].real();
  }
}

std::vector<double> BedRelief::layer(std::size_t l) const {
  std::vector<double> out(nx_ * ny_);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = values_[k * z_.size() + l];
  return out;
}

}  // namespace grainlab::ripples::hybrid
