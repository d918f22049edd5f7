#include "triangles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace grainlab::ripples {

namespace {

using State = std::array<double, 4>;  // s_U, l_U, s_D, l_D

struct Geometry {
  double K, cot_beta;
};

double flux(const TriangleParams& p, const Geometry& g, double exposed_stoss_height) {
  return p.law == "target" ? p.q0 : p.q0 / (exposed_stoss_height * g.cot_beta);
}

State rates(const TriangleParams& p, const Geometry& g, const State& x) {
  const double Hu = (x[1] - x[0]) / g.K, Hd = (x[3] - x[2]) / g.K;
  const double yi = std::max(0.0, (x[1] - x[2]) / g.K);  // the upstream lee on the downstream stoss
  const double Qu = flux(p, g, Hu), Qd = flux(p, g, Hd - yi);
  return {Qu / Hu, Qu / (Hu - yi), Qd / (Hd - yi), Qd / Hd};
}

}  // namespace

double triangle_speed(const TriangleParams& p, double H) {
  const Geometry g{1 / std::tan(p.beta_deg * M_PI / 180) + 1 / std::tan(p.alpha_deg * M_PI / 180),
                   1 / std::tan(p.beta_deg * M_PI / 180)};
  return flux(p, g, H) / H;
}

CollisionResult triangle_collision(const TriangleParams& p, double ratio) {
  if (p.law != "target" && p.law != "brink")
    throw std::invalid_argument("transport law must be target or brink");
  if (!(ratio > 0 && ratio < 1)) throw std::invalid_argument("the size ratio must lie in (0, 1)");
  const Geometry g{1 / std::tan(p.beta_deg * M_PI / 180) + 1 / std::tan(p.alpha_deg * M_PI / 180),
                   1 / std::tan(p.beta_deg * M_PI / 180)};
  // Downstream ripple of height 1 from x = 0; the upstream one's lee toe half a unit behind its stoss toe.
  State x{-ratio * g.K - 0.5, -0.5, 0, g.K};
  CollisionResult r;
  r.area_before = ratio * ratio + 1;
  r.min_effective_height = 1;
  // RK4; the step is a small fraction of the time the small ripple needs to cross its own base.
  const double h = 2e-3 * ratio * ratio * g.K / (p.law == "target" ? 1.0 : 1.0 / (ratio * g.cot_beta));
  bool touched = false;
  double t = 0, contact_start = 0;
  for (long n = 0; n < 100000000; ++n) {
    const State k1 = rates(p, g, x);
    State y;
    for (int i = 0; i < 4; ++i) y[i] = x[i] + h / 2 * k1[i];
    const State k2 = rates(p, g, y);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + h / 2 * k2[i];
    const State k3 = rates(p, g, y);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + h * k3[i];
    const State k4 = rates(p, g, y);
    for (int i = 0; i < 4; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    t += h;
    const double yi = (x[1] - x[2]) / g.K, Hu = (x[1] - x[0]) / g.K, Hd = (x[3] - x[2]) / g.K;
    if (yi > 0) {
      if (!touched) contact_start = t;
      touched = true;
      r.min_effective_height = std::min(r.min_effective_height, (Hu - yi) / ratio);
      r.duration = t - contact_start;
    }
    if (n % 200 == 0)
      r.t.push_back(t), r.h_up.push_back(Hu), r.h_down.push_back(Hd), r.y_i.push_back(std::max(0.0, yi));
    if (touched && yi < -0.5) break;  // apart again, by the distance they started at
  }
  r.upstream_after = (x[1] - x[0]) / g.K, r.downstream_after = (x[3] - x[2]) / g.K;
  r.area_after = r.upstream_after * r.upstream_after + r.downstream_after * r.downstream_after;
  return r;
}

double limiting_wavelength(double ratio, double critical_height, double beta_deg, double alpha_deg) {
  TriangleParams p;
  p.beta_deg = beta_deg, p.alpha_deg = alpha_deg;
  const double target = triangle_collision(p, ratio).min_effective_height;
  p.law = "brink";
  const double brink = triangle_collision(p, ratio).min_effective_height;
  const double mean_curve = 0.5 * (target + brink);
  const double H_down = critical_height / (ratio * mean_curve);
  const double K = 1 / std::tan(beta_deg * M_PI / 180) + 1 / std::tan(alpha_deg * M_PI / 180);
  return K * H_down * std::sqrt(1 + ratio * ratio);
}

}  // namespace grainlab::ripples
