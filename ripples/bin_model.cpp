#include "bin_model.hpp"

#include <cmath>
#include <complex>
#include <deque>

#include "rng.hpp"

namespace grainlab::ripples {

namespace {

int wrap(int i, int n) {
  return ((i % n) + n) % n;
}

}  // namespace

BinModel::BinModel(const BinModelParams& p)
    : p_(p), h_(static_cast<std::size_t>(p.bins)), unit_(1 / p.bin_width) {
  Rng rng(p.seed, 0);
  // Whole grains: each bin holds an integer count, so relaxation moves whole grains.
  for (double& x : h_) x = unit_ * std::floor((p.depth + rng.uniform(0, 2 * p.roughness)) / unit_);
  rng_state_ = p.seed;
}

int BinModel::hit_bin(int entry) {
  // The path drops tan(angle) x bin_width grain diameters per bin; it starts above the highest point.
  double top = 0;
  for (double x : h_) top = std::max(top, x);
  const double drop = std::tan(p_.impact_deg * M_PI / 180) * p_.bin_width;
  double y = top + drop;
  for (int k = 0; k < 100 * p_.bins; ++k) {
    const int i = wrap(entry + k, p_.bins);
    if (h_[static_cast<std::size_t>(i)] >= y) return i;
    y -= drop;
  }
  return entry;
}

void BinModel::relax(int around) {
  // Move grains down any step steeper than the angle of repose, until none is left near the disturbance.
  const double max_step = std::tan(p_.repose_deg * M_PI / 180) * p_.bin_width;
  std::deque<int> todo = {wrap(around - 1, p_.bins), around, wrap(around + 1, p_.bins)};
  for (long guard = 0; !todo.empty() && guard < 10000000; ++guard) {
    const int i = todo.front();
    todo.pop_front();
    for (const int j : {wrap(i - 1, p_.bins), wrap(i + 1, p_.bins)}) {
      double& hi = h_[static_cast<std::size_t>(i)];
      double& hj = h_[static_cast<std::size_t>(j)];
      if (hi - hj > max_step + 1e-12) {
        hi -= unit_, hj += unit_;
        todo.push_back(i), todo.push_back(j),
            todo.push_back(wrap(j + (j == wrap(i + 1, p_.bins) ? 1 : -1), p_.bins));
      }
    }
  }
}

void BinModel::fire(long shots) {
  Rng rng(p_.seed, 1000 + static_cast<std::uint64_t>(shots_));  // a fresh stream per call, keyed by progress
  for (long s = 0; s < shots; ++s) {
    const int entry = static_cast<int>(rng.uniform() * p_.bins) % p_.bins;
    const int hit = hit_bin(entry);
    if (h_[static_cast<std::size_t>(hit)] < unit_) continue;  // nothing to move
    const int to = wrap(hit + p_.hop_bins, p_.bins);
    h_[static_cast<std::size_t>(hit)] -= unit_;
    h_[static_cast<std::size_t>(to)] += unit_;
    relax(hit);
    relax(to);
  }
  shots_ += shots;
}

double BinModel::total_grains() const {
  double s = 0;
  for (double x : h_) s += x;
  return s / unit_;
}

double BinModel::rms_roughness() const {
  double m = 0, v = 0;
  for (double x : h_) m += x;
  m /= static_cast<double>(h_.size());
  for (double x : h_) v += (x - m) * (x - m);
  return std::sqrt(v / static_cast<double>(h_.size()));
}

double BinModel::dominant_wavelength() const {
  const std::size_t n = h_.size();
  double best = 0, best_power = -1;
  for (std::size_t k = 1; k <= n / 2; ++k) {
    std::complex<double> c = 0;
    for (std::size_t i = 0; i < n; ++i) c += h_[i] * std::polar(1.0, -2 * M_PI * double(k * i) / double(n));
    if (std::norm(c) > best_power) best_power = std::norm(c), best = double(n) / double(k);
  }
  return best;
}

}  // namespace grainlab::ripples
