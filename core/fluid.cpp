#include "fluid.hpp"

#include <algorithm>
#include <cmath>

namespace grainlab::fluid {

double drag_coefficient(WindSpec::DragLaw law, double re) {
  re = std::max(re, 1e-12);
  if (law == WindSpec::DragLaw::DallaValle) {
    const double s = 0.63 + 4.8 / std::sqrt(re);
    return s * s;
  }
  if (law == WindSpec::DragLaw::Huo2021) {  // C_d_inf = 0.5, Re_c = 24 (Huo et al. 2021, after Cheng)
    const double s = std::sqrt(0.5) + std::sqrt(24 / re);
    return s * s;
  }
  return 24 / re + 6 / (1 + std::sqrt(re)) + 0.4;  // eq. 4.31
}

double drag_rate(WindSpec::DragLaw law, const FluidSpec& f, double diameter, double speed_rel) {
  if (speed_rel <= 0) return 0;
  const double cd = drag_coefficient(law, diameter * speed_rel / f.viscosity);
  // f = 1/2 c_d rho_f |v| v pi d^2 / 4 over m = rho_g pi d^3 / 6.
  return 0.75 * cd * f.density * speed_rel / (f.grain_density * diameter);
}

namespace {
// du/dz at height z for kinematic stress s.
double shear_rate(const WindProfileInput& in, double z, double s) {
  if (s <= 0) return 0;
  if (in.model != WindSpec::Model::VanDriest) return std::sqrt(s) / (in.kappa * z);
  const double damping = in.u_star > 0 ? 1 - std::exp(-z * in.u_star / (26 * in.viscosity)) : 1;
  const double l = in.kappa * z * damping;
  // l^2 r^2 + nu r - s = 0, the root that stays finite as l -> 0.
  return 2 * s / (in.viscosity + std::sqrt(in.viscosity * in.viscosity + 4 * l * l * s));
}
}  // namespace

std::vector<double> wind_profile(const WindProfileInput& in, const std::vector<double>& z,
                                 const std::vector<double>& stress) {
  std::vector<double> u(z.size(), 0.0);
  double z_prev = in.roughness, u_prev = 0, s_prev = -1;
  for (std::size_t k = 0; k < z.size(); ++k) {
    if (z[k] <= in.roughness) continue;
    const double s = std::max(0.0, stress[k]);
    const double s_mid = s_prev < 0 ? s : 0.5 * (s + s_prev);
    if (z_prev <= 0) {  // a smooth wall (z0 = 0, van Driest): the midpoint rule from the wall itself
      u[k] = shear_rate(in, 0.5 * z[k], s_mid) * z[k];
    } else {  // midpoint in log z: exact for du/dz proportional to 1/z at constant stress
      const double zg = std::sqrt(z_prev * z[k]);
      u[k] = u_prev + shear_rate(in, zg, s_mid) * zg * std::log(z[k] / z_prev);
    }
    z_prev = z[k], u_prev = u[k], s_prev = s;
  }
  return u;
}

namespace {
double mixing_length(const WindProfileInput& in, double z) {
  if (z <= 0) return 0;
  const double l = in.kappa * z;
  if (in.model != WindSpec::Model::VanDriest || in.u_star <= 0) return l;
  return l * (1 - std::exp(-z * in.u_star / (26 * in.viscosity)));
}

// Faces are written as conductances G: the kinematic stress through face k is G (u[k+1] - u[k]) / dz.
// The eddy part is l^2 |du/dz| with l = kappa times the logarithmic mean of the two heights, which makes
// the discrete column exact for the log law at any cell size; the face onto the bed runs from z0 (rough
// wall: the held cell's u = 0 sits at z0).
double lower_height(const WindProfileInput& in, const std::vector<double>& z, std::size_t k) {
  return z[k] <= in.roughness ? std::max(in.roughness, 1e-300) : z[k];
}

double eddy_viscosity(const WindProfileInput& in, double dz, const std::vector<double>& z,
                      const std::vector<double>& u, std::size_t k) {
  if (z[k + 1] <= in.roughness) return 0;
  const double z1 = lower_height(in, z, k), z2 = z[k + 1], lg = std::log(z2 / z1);
  const double damping = mixing_length(in, 0.5 * (z1 + z2)) / (in.kappa * 0.5 * (z1 + z2));
  // l^2 |du/dz| dz-normalised: kappa^2 damping^2 |du| dz / ln(z2/z1)^2.
  return in.kappa * in.kappa * damping * damping * std::abs(u[k + 1] - u[k]) * dz / (lg * lg);
}

// The molecular part (van Driest only; the thesis's mixing length has none). A floor far below any
// turbulent value keeps a still layer from decoupling from the wind above.
double molecular(const WindProfileInput& in, double dz, const std::vector<double>& z, std::size_t k) {
  const double nu = (in.model == WindSpec::Model::VanDriest ? in.viscosity : 0.0) + 1e-9 * in.viscosity;
  const double span = z[k + 1] - (z[k] <= in.roughness ? in.roughness : z[k]);
  return nu * dz / std::max(span, 1e-3 * dz);
}
}  // namespace

double face_conductance(const WindProfileInput& in, double dz, const std::vector<double>& z,
                        const std::vector<double>& u, std::size_t k) {
  return eddy_viscosity(in, dz, z, u, k) + molecular(in, dz, z, k);
}

double face_stress(const WindProfileInput& in, double dz, const std::vector<double>& z,
                   const std::vector<double>& u, std::size_t k) {
  return face_conductance(in, dz, z, u, k) * (u[k + 1] - u[k]) / dz;
}

std::vector<double> advance_wind_column(const WindProfileInput& in, double dz, const std::vector<double>& z,
                                        const std::vector<double>& u, const std::vector<double>& a,
                                        const std::vector<double>& b, double dt, std::vector<double>& eddy) {
  const std::size_t n = u.size();
  if (eddy.size() != n - 1) {
    eddy.resize(n - 1);
    for (std::size_t k = 0; k + 1 < n; ++k) eddy[k] = eddy_viscosity(in, dz, z, u, k);
  }
  const double inv_dt = std::isfinite(dt) ? 1 / dt : 0.0;
  // Tridiagonal rows lo u[k-1] + di u[k] + up u[k+1] = rhs, solved by the Thomas algorithm.
  std::vector<double> lo(n, 0.0), di(n, 1.0), up(n, 0.0), rhs(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    if (z[k] <= in.roughness) continue;  // held at rest
    const double below = k > 0 ? (eddy[k - 1] + molecular(in, dz, z, k - 1)) / (dz * dz) : 0.0;
    const double above = k + 1 < n ? (eddy[k] + molecular(in, dz, z, k)) / (dz * dz) : 0.0;
    lo[k] = -below, up[k] = -above;
    di[k] = inv_dt + below + above + a[k];
    rhs[k] = u[k] * inv_dt + b[k] + (k + 1 == n ? in.u_star * in.u_star / dz : 0.0);
  }
  for (std::size_t k = 1; k < n; ++k) {
    const double m = lo[k] / di[k - 1];
    di[k] -= m * up[k - 1];
    rhs[k] -= m * rhs[k - 1];
  }
  std::vector<double> next(n);
  next[n - 1] = rhs[n - 1] / di[n - 1];
  for (std::size_t k = n - 1; k-- > 0;) next[k] = (rhs[k] - up[k] * next[k + 1]) / di[k];
  // The next viscosity: the geometric mean of the one used and the one the new shear gives. Taking the
  // new shear's alone maps s -> tau / (l^2 s) and oscillates forever; the mean lands on the fixed point
  // s = sqrt(tau) / l in one pass where the stress is uniform.
  // (A floor keeps a face that went still from staying still once stress reaches it again.)
  const double floor = 1e-6 * in.viscosity;
  for (std::size_t k = 0; k + 1 < n; ++k)
    eddy[k] = std::sqrt((eddy[k] + floor) * (eddy_viscosity(in, dz, z, next, k) + floor));
  return next;
}

double transport_law_mass(double shields, double shields_threshold, double mu_b) {
  return std::max(0.0, shields - shields_threshold) / mu_b;
}

double transport_law_velocity(double shields, double shields_threshold, double kappa, double mu_b,
                              double c_m) {
  if (shields <= shields_threshold) return 0;
  return 2 * std::sqrt(shields_threshold) / kappa * (1 + c_m / mu_b * (shields - shields_threshold));
}

}  // namespace grainlab::fluid
