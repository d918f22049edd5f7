#include "conveyor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <stdexcept>

#include "convergence.hpp"

namespace grainlab::saltation {

namespace {

// The root of an increasing function on (0, infinity), by doubling then bisection.
double increasing_root(const std::function<double(double)>& g) {
  double lo = 0, hi = 1;
  while (g(hi) < 0 && hi < 1e12) lo = hi, hi *= 2;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double relative_change(double a, double b) {
  return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

// The impact speed at the bed of a grain launched at v_oy with the belt at v_c (eq. 4.1 with v_ciy = v_oy).
double impact_speed(double v_c, double v_oy) {
  return v_c * v_oy / (v_c + v_oy);
}

// One step of eq. 4.23 from (F, v_oy) with the belt solved for them.
MapState map_step(const ConveyorMapParams& p, const MapState& s) {
  MapState n = s;
  const double vx = impact_speed(s.v_c, s.v_oy);
  const double N = vx * vx / (p.v_g * p.v_g);
  const double f = p.f_at(vx);
  n.v_oy = s.v_oy * (p.eps * p.eps + f * s.v_c / (s.v_c + s.v_oy)) / std::sqrt(N);
  if (p.order == "velocity-first") {
    const double v_c = belt_speed_for_map(p, s.F, n.v_oy);
    const double vx2 = impact_speed(v_c, n.v_oy);
    n.F = s.F * vx2 * vx2 / (p.v_g * p.v_g);
  } else {
    n.F = s.F * N;
  }
  n.v_c = belt_speed_for_map(p, n.F, n.v_oy);
  const double vxn = impact_speed(n.v_c, n.v_oy);
  n.N = vxn * vxn / (p.v_g * p.v_g);
  return n;
}

}  // namespace

DeltaSteadyState conveyor_delta_steady(double f, double eps, double v_g, double P_T, double zeta) {
  DeltaSteadyState s;
  const double loss = 1 - eps * eps;
  if (f <= loss) return s;  // the bed cannot send a grain back up as fast as it came: no steady state
  s.v_bix = v_g;
  s.v_biy = -eps * f * v_g / loss;
  s.v_boy = f * v_g / loss;
  s.v_c = v_g / (1 - loss / f);
  const double per_flux = 1 - loss / f;
  s.F = std::max(0.0, (P_T / (s.v_c * s.v_c) - zeta) / per_flux);
  s.transport = s.F > 0;
  s.P_g = s.F * s.v_c * s.v_c * per_flux;
  return s;
}

double ConveyorMapParams::f_at(double v_bix) const {
  if (f_max == f_min || f_v2 <= f_v1) return f_max;
  const double t = std::clamp((v_bix - f_v1) / (f_v2 - f_v1), 0.0, 1.0);
  return f_max + (f_min - f_max) * t;
}

ConveyorMapParams table_4_2(const std::string& c) {
  ConveyorMapParams p;
  if (c == "D") return p;
  if (c == "E") {
    // f(v_bix) = 0.8 until 1 - 0.736 w, 0.6 from there + w (w = 0.15): f(1) = 0.6528, the f at which the
    // steady state of eq. 4.3 has F = 20 at P_T = 1000.
    p.f_min = 0.6, p.f_v1 = 1 - 0.736 * 0.15, p.f_v2 = p.f_v1 + 0.15;
    return p;
  }
  throw std::invalid_argument("Table 4.2 has CASES D and E");
}

double belt_speed_for_map(const ConveyorMapParams& p, double F, double v_oy) {
  return increasing_root(
      [&](double v_c) { return F * v_c * impact_speed(v_c, v_oy) + p.zeta * v_c * v_c - p.P_T; });
}

ConveyorMapResult conveyor_map(const ConveyorMapParams& p, double F0, double v_oy0, int max_iterations,
                               double tol) {
  if (p.order != "simultaneous" && p.order != "velocity-first")
    throw std::invalid_argument("conveyor map order must be \"simultaneous\" or \"velocity-first\"");
  ConveyorMapResult r;
  MapState s;
  s.F = F0, s.v_oy = v_oy0, s.v_c = belt_speed_for_map(p, F0, v_oy0);
  const double vx = impact_speed(s.v_c, s.v_oy);
  s.N = vx * vx / (p.v_g * p.v_g);
  r.history.push_back(s);
  for (int n = 0; n < max_iterations; ++n) {
    const MapState next = map_step(p, s);
    const double change = std::max(
        {relative_change(next.F, s.F), relative_change(next.v_oy, s.v_oy), relative_change(next.v_c, s.v_c)});
    r.residuals.push_back(change);
    r.history.push_back(next);
    s = next;
    r.iterations = n + 1;
    if (!std::isfinite(change)) break;
    if (change < tol) {
      r.converged = true;
      break;
    }
  }
  return r;
}

ConveyorLinearization conveyor_linearization(const ConveyorMapParams& p, const MapState& z) {
  ConveyorLinearization L;
  // Central differences of the one-step map in (v_oy, F), the belt re-solved each time.
  const double x[2] = {z.v_oy, z.F};
  for (int j = 0; j < 2; ++j) {
    const double h = 1e-6 * x[j];
    MapState plus = z, minus = z;
    (j == 0 ? plus.v_oy : plus.F) += h;
    (j == 0 ? minus.v_oy : minus.F) -= h;
    plus.v_c = belt_speed_for_map(p, plus.F, plus.v_oy);
    minus.v_c = belt_speed_for_map(p, minus.F, minus.v_oy);
    const MapState a = map_step(p, plus), b = map_step(p, minus);
    L.jacobian[0][j] = (a.v_oy - b.v_oy) / (2 * h);
    L.jacobian[1][j] = (a.F - b.F) / (2 * h);
  }
  const double tr = L.jacobian[0][0] + L.jacobian[1][1];
  const double det = L.jacobian[0][0] * L.jacobian[1][1] - L.jacobian[0][1] * L.jacobian[1][0];
  const std::complex<double> root = std::sqrt(std::complex<double>(tr * tr / 4 - det));
  L.eigenvalues[0] = tr / 2 + root, L.eigenvalues[1] = tr / 2 - root;
  const double e = p.eps, f = p.f_at(impact_speed(z.v_c, z.v_oy)), vo = z.v_oy, vc = z.v_c;
  L.A11 = -e * f * vo * vo * vc / ((e + 1) * (vc + vo) * (vc + vo));
  L.B11 = e * f * vo * vo * vo / ((e + 1) * (vc + vo) * (vc + vo));
  L.B12 = -0.5 * e * vo * vo / (e + 1);
  L.B22 = e * vo * z.F / (e + 1);
  return L;
}

DistributionSplashParams table_4_1(const std::string& c) {
  DistributionSplashParams p;  // CASE A's values
  if (c == "A") return p;
  if (c == "B") {
    p.gamma = 0.004, p.delta = 0.2;
    return p;
  }
  if (c == "C") {
    p.gamma = 0.2, p.delta = 0.5;
    return p;
  }
  throw std::invalid_argument("Table 4.1 has CASES A, B and C");
}

double conveyor_kernel(const DistributionSplashParams& p, double v, double vp, double v_c) {
  const double vx = impact_speed(v_c, vp);  // the impact's horizontal speed; its vertical is eps v'
  const double centre = p.f * vx + p.eps * p.eps * vp;
  const double rebound = p.alpha * (vx / (vx + p.e5)) * std::exp(-(v - centre) * (v - centre) / p.beta);
  const double ejecta = p.gamma * vx * vx * std::exp(-v / p.delta);
  return rebound + ejecta;
}

DistributionResult conveyor_distribution(const DistributionSplashParams& p, int max_iterations, double tol,
                                         const std::vector<double>& start) {
  DistributionResult r;
  const int M = p.bins;
  for (int i = 0; i < M; ++i) r.mu.push_back((i + 0.5) * p.dmu);
  // A broad start by default: a start concentrated below mu = 1 nearly kills the flux for hundreds of
  // steps (spec).
  if (!start.empty() && start.size() != static_cast<std::size_t>(M))
    throw std::invalid_argument("conveyor_distribution: the start has " + std::to_string(start.size()) +
                                " bins, the grid " + std::to_string(M));
  r.F = start.empty() ? std::vector<double>(static_cast<std::size_t>(M), 1.0) : start;
  auto belt = [&](const std::vector<double>& F) {
    return increasing_root([&](double v_c) {
      double s = 0;
      for (int i = 0; i < M; ++i)
        s += F[static_cast<std::size_t>(i)] * impact_speed(v_c, r.mu[static_cast<std::size_t>(i)]) * p.dmu;
      return v_c * s + p.zeta * v_c * v_c - p.P_T;
    });
  };
  r.v_c = belt(r.F);
  std::vector<double> next(static_cast<std::size_t>(M));
  FluxWatch flux;
  for (int n = 0; n < max_iterations; ++n) {
    for (int i = 0; i < M; ++i) {
      double s = 0;
      for (int j = 0; j < M; ++j)
        s += conveyor_kernel(p, r.mu[static_cast<std::size_t>(i)], r.mu[static_cast<std::size_t>(j)], r.v_c) *
             r.F[static_cast<std::size_t>(j)] * p.dmu;
      next[static_cast<std::size_t>(i)] = s;
    }
    const double v_c = belt(next);
    const double fmax = *std::max_element(next.begin(), next.end());
    double change = relative_change(v_c, r.v_c);
    for (int i = 0; i < M; ++i)
      change =
          std::max(change, std::abs(next[static_cast<std::size_t>(i)] - r.F[static_cast<std::size_t>(i)]) /
                               std::max(fmax, 1e-300));
    r.F = next, r.v_c = v_c;
    r.residuals.push_back(change);
    r.iterations = n + 1;
    if (!std::isfinite(change) || fmax <= 0) break;
    // F = 0 is a fixed point too: the belt at its speed without grains, sqrt(P_T / zeta).
    if (flux.dying(std::accumulate(next.begin(), next.end(), 0.0))) {
      r.failure = fmt::format(
          "the flux died out after {} iterations: from this start the belt runs near its speed without "
          "grains ({:.4g} at the end), the rebounds climb past the top of the velocity grid and are lost "
          "faster than they replace themselves; start from a broad distribution",
          n + 1, v_c);
      break;
    }
    if (change < tol) {
      r.converged = true;
      break;
    }
  }
  if (!r.converged && r.failure.empty()) r.failure = why_not_converged(r.residuals, tol);
  return r;
}

}  // namespace grainlab::saltation
