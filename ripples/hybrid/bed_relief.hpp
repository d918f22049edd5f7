#pragma once
// The bed's relief as the wind above it feels it. Over a low, periodic bed, potential flow lifts its
// streamlines by each Fourier mode of the relief (the bed less its mean level) times exp(-|k| s) at a
// height s above the bed: short waves are felt only near the bed, long ones higher up. The wind column
// then stands, at height s, on the bed's relief as it has faded there (the column on the mean level and
// the column on the bed beneath each grain are the limits k -> infinity and k -> 0). Computed once per
// wind update on a few heights (an FFT of the key points' grid) and read per grain by interpolation.
#include <array>
#include <complex>
#include <cstddef>
#include <vector>

namespace grainlab::ripples::hybrid {

class BedRelief {
 public:
  // A periodic grid of nx x ny key points `cell` apart (cm); heights of the layers are in units of d (cm).
  BedRelief(std::size_t nx, std::size_t ny, double cell, double d);
  // The relief of `heights` (x fastest, as HeightField's) about `mean`, at every layer's height.
  void refresh(const std::vector<double>& heights, double mean);
  // The relief felt at (x, y) (inside the box), s >= 0 above the bed (cm), given the bed's own relief
  // there (at s = 0, where the surface is followed exactly): linear in s between the layers, bilinear
  // between key points, fading to zero over the top layer's height above it.
  double at(double x, double y, double s, double relief_at_bed) const;
  // The layers' heights above the bed (cm) and a layer's values (x fastest; a copy, valid until the
  // next call): for tests and plots.
  const std::vector<double>& heights() const { return z_; }
  const std::vector<double>& layer(std::size_t l) const;

 private:
  std::array<double, 2> pair_at(std::size_t l, double x, double y) const;
  std::size_t nx_, ny_;
  double cell_, inv_cell_;
  std::vector<double> z_;  // above the bed, cm, ascending (the first > 0)
  // Per key point (x fastest), the faded relief at every height in turn: a grain reads two heights at
  // four key points, 16 bytes at each.
  std::vector<double> values_;
  mutable std::vector<double> column_;       // layer()'s copy
  std::vector<std::complex<double>> modes_;  // scratch: the relief's spectrum
};

}  // namespace grainlab::ripples::hybrid
