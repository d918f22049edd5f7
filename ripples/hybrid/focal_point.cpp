#include "focal_point.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void require_same_heights(const WindProfile& a, const WindProfile& b) {
  if (a.z != b.z || a.u.size() != a.z.size() || b.u.size() != b.z.size())
    throw std::invalid_argument("the wind profiles must share their heights");
}

// The profile at the heights `z` (inside its own range), linear in ln z between its nodes.
WindProfile resampled(const WindProfile& p, const std::vector<double>& z) {
  WindProfile r{p.u_star, z, {}};
  std::size_t k = 0;
  for (double h : z) {
    while (k + 2 < p.z.size() && p.z[k + 1] < h) ++k;
    const double a = (std::log(h) - std::log(p.z[k])) / (std::log(p.z[k + 1]) - std::log(p.z[k]));
    r.u.push_back(p.u[k] + std::clamp(a, 0.0, 1.0) * (p.u[k + 1] - p.u[k]));
  }
  return r;
}

// Heights every profile covers, evenly spaced in ln z: the columns' meshes differ with u* (their first node
// sits in the viscous sublayer).
std::vector<double> common_heights(const std::vector<WindProfile>& profiles) {
  double lo = 0, hi = INFINITY;
  for (const WindProfile& p : profiles) {
    if (p.z.size() < 2 || p.u.size() != p.z.size() || !(p.z.front() > 0))
      throw std::invalid_argument("a wind profile needs two or more positive heights, each with its wind");
    lo = std::max(lo, p.z.front()), hi = std::min(hi, p.z.back());
  }
  if (!(hi > lo)) throw std::invalid_argument("the wind profiles share no range of heights");
  constexpr int kPoints = 480;
  std::vector<double> z;
  for (int k = 0; k < kPoints; ++k) z.push_back(lo * std::pow(hi / lo, k / double(kPoints - 1)));
  return z;
}

}  // namespace

LogLayerFit log_layer_roughness(const WindProfile& p, double z_lo, double z_hi, double kappa) {
  if (!(p.u_star > 0)) throw std::invalid_argument("a wind profile needs u* > 0");
  double sum = 0, lo = INFINITY, hi = -INFINITY;
  std::size_t n = 0;
  for (std::size_t k = 0; k < p.z.size() && k < p.u.size(); ++k) {
    if (p.z[k] < z_lo || p.z[k] > z_hi || !(p.z[k] > 0)) continue;
    const double ln_z0 = std::log(p.z[k]) - kappa * p.u[k] / p.u_star;
    sum += ln_z0, lo = std::min(lo, ln_z0), hi = std::max(hi, ln_z0), ++n;
  }
  if (n == 0) throw std::invalid_argument("no node of the wind profile lies in the log-layer band");
  return {std::exp(sum / static_cast<double>(n)), hi - lo, n};
}

std::optional<ProfileCrossing> profile_crossing(const WindProfile& a, const WindProfile& b, double z_min) {
  require_same_heights(a, b);
  const std::vector<double>& z = a.z;
  for (std::size_t k = 0; k + 1 < z.size(); ++k) {
    if (z[k] < z_min || !(z[k] > 0)) continue;
    const double d0 = a.u[k] - b.u[k], d1 = a.u[k + 1] - b.u[k + 1];
    if (d0 == 0) return ProfileCrossing{a.u_star, b.u_star, z[k], a.u[k]};
    if ((d0 < 0) == (d1 < 0)) continue;
    const double f = d0 / (d0 - d1);  // where the difference is zero between the nodes
    return ProfileCrossing{a.u_star, b.u_star, std::exp(std::log(z[k]) + f * std::log(z[k + 1] / z[k])),
                           a.u[k] + f * (a.u[k + 1] - a.u[k])};
  }
  return std::nullopt;
}

FocalPoint focal_point(const std::vector<WindProfile>& profiles, double z_lo, double z_hi, double z_min,
                       double kappa) {
  if (profiles.size() < 2) throw std::invalid_argument("a focal point needs at least two wind profiles");
  FocalPoint f;
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (const WindProfile& p : profiles) {
    f.log_layers.push_back(log_layer_roughness(p, z_lo, z_hi, kappa));
    const double x = 1 / p.u_star, y = std::log(f.log_layers.back().z0);
    sx += x, sy += y, sxx += x * x, sxy += x * y, syy += y * y;
  }
  const double n = static_cast<double>(profiles.size());
  const double vxx = sxx - sx * sx / n, vxy = sxy - sx * sy / n, vyy = syy - sy * sy / n;
  if (!(vxx > 0)) throw std::invalid_argument("a focal point needs wind profiles at different u*");
  const double slope = vxy / vxx, intercept = (sy - slope * sx) / n;
  f.fit_z = std::exp(intercept), f.fit_u = -slope / kappa;
  f.fit_r2 = vyy > 0 ? vxy * vxy / (vxx * vyy) : 1;
  const std::vector<double> z = common_heights(profiles);
  std::vector<WindProfile> on_grid;
  for (const WindProfile& p : profiles) on_grid.push_back(resampled(p, z));
  std::vector<double> zs, us;
  for (std::size_t i = 0; i < on_grid.size(); ++i)
    for (std::size_t j = i + 1; j < on_grid.size(); ++j) {
      ++f.pairs;
      if (const auto c = profile_crossing(on_grid[i], on_grid[j], z_min)) {
        f.crossings.push_back(*c);
        zs.push_back(c->z), us.push_back(c->u);
      }
    }
  if (!zs.empty()) {
    f.crossing_z = median(zs), f.crossing_u = median(us);
    f.crossing_z_min = *std::min_element(zs.begin(), zs.end());
    f.crossing_z_max = *std::max_element(zs.begin(), zs.end());
  }
  return f;
}

}  // namespace grainlab::ripples::hybrid
