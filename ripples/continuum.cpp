#include "continuum.hpp"

#include <cmath>

namespace grainlab::ripples {

double ContinuumParams::anti_diffusivity() const {
  return a * d * d * F_x / std::tan(alpha_deg * M_PI / 180);
}

double impact_flux_on_slope(double slope, double alpha_deg) {
  return (1 + slope / std::tan(alpha_deg * M_PI / 180)) / std::sqrt(1 + slope * slope);
}

void advance_continuum(const ContinuumParams& p, std::vector<double>& h, int steps) {
  const std::size_t n = h.size();
  std::vector<double> R(n);  // R[i]: reptation flux across the face between bins i and i + 1
  for (int s = 0; s < steps; ++s) {
    for (std::size_t i = 0; i < n; ++i) {
      const double slope = (h[(i + 1) % n] - h[i]) / p.dx;
      R[i] = p.a * p.F_x * impact_flux_on_slope(slope, p.alpha_deg);
    }
    for (std::size_t i = 0; i < n; ++i)
      h[i] -= p.dt * p.d * p.d * (R[i] - R[(i + n - 1) % n]) / p.dx;  // eq. 5.3
  }
}

double continuum_growth_per_step(const ContinuumParams& p, double k) {
  return 1 + p.dt * p.anti_diffusivity() * (2 - 2 * std::cos(k * p.dx)) / (p.dx * p.dx);
}

double steady_length(const ContinuumParams& p, double v) {
  return p.anti_diffusivity() / v;  // a d^2 F_x / (v tan alpha)
}

double steady_shape(const ContinuumParams& p, double v, double C, double h0, double s) {
  const double lambda = steady_length(p, v);
  return C * std::exp(s / lambda) + lambda * std::tan(p.alpha_deg * M_PI / 180) + h0;
}

std::vector<double> integrate_steady_shape(const ContinuumParams& p, double v, double h0, double h_start,
                                           double ds, int n) {
  const double lambda = steady_length(p, v), tan_a = std::tan(p.alpha_deg * M_PI / 180);
  auto slope = [&](double h) { return (h - h0) / lambda - tan_a; };
  std::vector<double> h{h_start};
  for (int i = 0; i < n; ++i) {
    const double y = h.back(), k1 = slope(y), k2 = slope(y + ds / 2 * k1), k3 = slope(y + ds / 2 * k2),
                 k4 = slope(y + ds * k3);
    h.push_back(y + ds / 6 * (k1 + 2 * k2 + 2 * k3 + k4));
  }
  return h;
}

}  // namespace grainlab::ripples
