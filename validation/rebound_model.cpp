#include "rebound_model.hpp"

#include <cmath>
#include <limits>
#include <optional>

namespace grainlab::validation {

namespace {

constexpr double kDeg = M_PI / 180;

struct Hit {
  double s;  // distance along the unit direction
  long k;    // bed disc index
};

// First bed disc (centres at (k L, 0), r_b = 1) that a disc of radius rho moving from (x, y) along the
// unit direction (dx, dy) touches, skipping disc `skip`. Lengths are in r_b.
std::optional<Hit> first_hit(double x, double y, double dx, double dy, double rho, double period, long skip) {
  const double reach = 1 + rho;
  // The path can meet discs only while its centre is within `reach` of the layer (|y| <= reach).
  double s_max = 1e9;
  if (dy < 0) s_max = (y + reach) / -dy;
  if (dy > 0) s_max = std::max(0.0, (reach - y) / dy);
  if (dy == 0 && std::abs(y) > reach) return std::nullopt;
  if (s_max > 1e6) s_max = 1e6;
  const double x_end = x + dx * s_max;
  const long k0 = static_cast<long>(std::floor((std::min(x, x_end) - reach) / period)) - 1;
  const long k1 = static_cast<long>(std::ceil((std::max(x, x_end) + reach) / period)) + 1;
  std::optional<Hit> best;
  for (long k = k0; k <= k1; ++k) {
    if (k == skip) continue;
    const double ox = x - k * period, oy = y;
    const double b = ox * dx + oy * dy, c = ox * ox + oy * oy - reach * reach;
    const double disc = b * b - c;
    if (disc < 0) continue;
    const double s = -b - std::sqrt(disc);  // entering the contact circle
    if (s < 1e-12 || (best && s >= best->s)) continue;
    best = Hit{s, k};
  }
  return best;
}

}  // namespace

ReboundParams rebound_case(int which, double alpha_deg) {
  ReboundParams p;
  p.alpha_deg = alpha_deg;
  p.radius_ratio = 1, p.mass_ratio = 0.5, p.bed_gap = 0, p.spin = 0, p.kappa_i = 0.5;
  if (which == 1) {
    p.kappa_beff = 0.5, p.restitution = 0.6, p.sigma = 1;
  } else {
    p.kappa_beff = 1.0, p.restitution = 0.85, p.sigma = 0;
  }
  return p;
}

void rebound_collision(const ReboundParams& p, double nx, double ny, double& vx, double& vy, double& w) {
  // c1 with "+": the OCR prints "-", but the tangential impulse on a target of mass m_beff and inertia
  // kappa_beff m_beff r_b^2 gives "+" (docs/impacts.md), and only "+" reproduces Table 3.10's trends.
  const double mr = p.mass_ratio;
  const double c1 = 1 / p.kappa_i + mr * (1 + 1 / p.kappa_beff);
  const double c2 = (p.sigma + c1) / (1 + c1), c3 = (1 - p.sigma) / (1 + c1);
  const double c4 = (p.restitution - mr) / (1 + mr);
  const double tx = ny, ty = -nx;  // t = (cos b, sin b) when n = (-sin b, cos b)
  const double vn = vx * nx + vy * ny, vt = vx * tx + vy * ty;
  const double wr = w * p.radius_ratio;  // w r_i in units of r_b / time
  const double vn_out = -c4 * vn, vt_out = c2 * vt - c3 * wr;
  // The tangential impulse (per unit incident mass, along t) also spins the incident grain: the contact
  // sits at -r_i n, so d(w r_i) = impulse / kappa_i.
  const double impulse = vt_out - vt;
  const double wr_new = wr + impulse / p.kappa_i;
  vx = vn_out * nx + vt_out * tx;
  vy = vn_out * ny + vt_out * ty;
  w = wr_new / p.radius_ratio;
}

ReboundAverages rebound_model(const ReboundParams& p) {
  ReboundAverages out;
  const double a = p.alpha_deg * kDeg, rho = p.radius_ratio, period = 2 + p.bed_gap;
  const double dx0 = std::cos(a), dy0 = -std::sin(a), height = 1 + rho + 1;
  const int n = p.impact_points;
  double sum_ix = 0, sum_iy = 0, sum_i = 0, sum_theta = 0, sum_beta = 0;
  int rebounds = 0, hits = 0, nabbed = 0, below = 0;
  for (int q = 0; q < n; ++q) {
    ReboundSample s;
    // Start points uniform along a horizontal line: a uniform stream, so each target is hit in
    // proportion to its exposed width.
    const double x = period * (q + 0.5) / n - height * dx0 / -dy0;
    double px = x, py = height, vx = dx0, vy = dy0, w = p.spin;  // velocities in units of v_i
    long last = std::numeric_limits<long>::min();
    bool escaped = false;
    for (int c = 0; c < 3; ++c) {
      const double speed = std::hypot(vx, vy);
      const auto hit = first_hit(px, py, vx / speed, vy / speed, rho, period, last);
      if (!hit) {
        escaped = vy > 0;  // up and clear; down through a gap is nabbed
        break;
      }
      if (c == 2) break;  // a third strike: nabbed
      px += hit->s * vx / speed, py += hit->s * vy / speed;
      const double nx = (px - hit->k * period) / (1 + rho), ny = py / (1 + rho);
      if (c == 0) {
        s.beta_deg = std::atan2(-nx, ny) / kDeg;
        sum_beta += s.beta_deg, ++hits;
      }
      rebound_collision(p, nx, ny, vx, vy, w);
      ++s.collisions;
      last = hit->k;
      if (vx * nx + vy * ny <= 0) break;  // still moving into the target: it would strike again
    }
    if (s.collisions == 0) continue;  // a gap wide enough to miss every disc: not an impact
    if (escaped) {
      s.eps_ix = vx / dx0, s.eps_iy = vy / -dy0, s.spin_out = w * rho;
      sum_ix += s.eps_ix, sum_iy += s.eps_iy, sum_i += std::hypot(vx, vy);
      sum_theta += std::atan2(vx, vy) / kDeg, ++rebounds;
    } else {
      s.nabbed = true, ++nabbed;
    }
    if (s.eps_iy < 1) ++below;
    out.samples.push_back(s);
  }
  const double m = static_cast<double>(out.samples.size());
  if (m == 0) return out;
  out.eps_ix = sum_ix / m, out.eps_iy = sum_iy / m, out.eps_i = sum_i / m;
  out.theta_i_deg = rebounds ? sum_theta / rebounds : 0;
  out.beta_deg = hits ? sum_beta / hits : 0;
  out.nabbed_fraction = nabbed / m, out.below_one_fraction = below / m;
  return out;
}

}  // namespace grainlab::validation
