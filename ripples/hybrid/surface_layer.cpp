#include "surface_layer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

SurfaceLayer::SurfaceLayer(std::size_t points, std::vector<double> fractions, double psi0)
    : f0_(std::move(fractions)), psi0_(psi0) {
  double sum = 0;
  for (double f : f0_) {
    if (!(f > 0)) throw std::invalid_argument("every size class needs a positive fraction of the bed");
    sum += f;
  }
  if (f0_.empty() || std::abs(sum - 1) > kFractionTolerance)
    throw std::invalid_argument("the size classes' fractions must sum to 1");
  for (double& f : f0_) f /= sum;
  if (!(psi0 > 0) || !std::isfinite(psi0))
    throw std::invalid_argument("the affectable depth must be positive");
  a_.assign(points * f0_.size(), 0.0);
  for (std::size_t k = 0; k < points; ++k) mix_in(k, psi0_);
}

void SurfaceLayer::mix_in(std::size_t k, double depth) {
  for (std::size_t c = 0; c < kinds(); ++c) a_[k * kinds() + c] += depth * f0_[c];
}

double SurfaceLayer::depth(std::size_t k) const {
  double psi = 0;
  for (std::size_t c = 0; c < kinds(); ++c) psi += a_[k * kinds() + c];
  return psi;
}

int SurfaceLayer::draw(std::size_t k, double u) const {
  double left = u * depth(k);
  for (std::size_t c = 0; c + 1 < kinds(); ++c)
    if ((left -= a_[k * kinds() + c]) < 0) return static_cast<int>(c);
  return static_cast<int>(kinds() - 1);
}

void SurfaceLayer::add(std::size_t k, int kind, double dh) {
  a_[k * kinds() + static_cast<std::size_t>(kind)] += dh;
}

void SurfaceLayer::take(std::size_t k, int kind, double dh) {
  double& mine = a_[k * kinds() + static_cast<std::size_t>(kind)];
  // Not enough of this class in the layer: it reaches down into the initial mix until there is.
  if (mine < dh) mix_in(k, (dh - mine) / f0_[static_cast<std::size_t>(kind)]);
  mine = std::max(0.0, mine - dh);
  // The resizing step took the layer below psi0: it shifts down, refilled from below.
  const double psi = depth(k);
  if (psi < psi0_) mix_in(k, psi0_ - psi);
}

double SurfaceLayer::mean_size(std::size_t k, const std::vector<double>& sizes) const {
  double sum = 0;
  for (std::size_t c = 0; c < kinds(); ++c) sum += a_[k * kinds() + c] * sizes[c];
  return sum / depth(k);
}

void SurfaceLayer::restore(const std::vector<double>& amounts) {
  if (amounts.size() != a_.size())
    throw std::invalid_argument("the checkpoint's surface layer has another size");
  for (double v : amounts)
    if (!(v >= 0) || !std::isfinite(v))
      throw std::invalid_argument("the checkpoint's surface layer is damaged");
  a_ = amounts;
}

}  // namespace grainlab::ripples::hybrid
