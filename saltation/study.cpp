#include "study.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fluid.hpp"

namespace grainlab::saltation {

Planet planet_preset(const std::string& name) {
  // Dynamic viscosities: air 1.8e-4 P (the thesis's nu 0.146 cm^2/s at its density); CO2 ~1.1e-4 P at Mars's
  // ~210 K and ~3.3e-4 P at Venus's ~735 K; nu = mu / rho.
  if (name == "earth") return {"earth", 981, 0.00123, 0.146};
  if (name == "mars") return {"mars", 371, 2.0e-5, 1.1e-4 / 2.0e-5};
  if (name == "venus") return {"venus", 887, 0.065, 3.3e-4 / 0.065};
  throw std::invalid_argument("unknown planet '" + name + "' (earth, mars, venus)");
}

std::vector<std::string> planet_names() {
  return {"earth", "mars", "venus"};
}

AnalyticSplash scaled(const AnalyticSplash& a, double s) {
  AnalyticSplash b = a;
  b.c2 *= s, b.c4 *= s, b.c5 *= s, b.c3 /= s * s * s;
  return b;
}

double clean_wind_growth(const WindModelOptions& o, const SplashKernel& splash) {
  // The log wind on the model's grid, one flight per launch bin, then the Perron root of [T] by power
  // iteration ([T] >= 0).
  std::vector<double> y(static_cast<std::size_t>(o.heights)), u(y.size());
  const double a = std::log(o.roughness()), b = std::log(o.top);
  for (std::size_t k = 0; k < y.size(); ++k) {
    y[k] = std::exp(a + (b - a) * static_cast<double>(k) / (o.heights - 1));
    u[k] = o.fluid.k * o.u_star * std::log(y[k] / y[0]);
  }
  const std::size_t M = static_cast<std::size_t>(o.bins);
  std::vector<double> v(M), vix(M), viy(M);
  for (std::size_t j = 0; j < M; ++j) {
    v[j] = (j + 0.5) * o.dv;
    const Trajectory t = fly(o, y, u, 0, v[j]);
    vix[j] = t.v_ix, viy[j] = t.v_iy;
  }
  std::vector<double> x(M, 1.0), next(M);
  double lambda = 0;
  for (int it = 0; it < 500; ++it) {
    double norm = 0;
    for (std::size_t k = 0; k < M; ++k) {
      double s = 0;
      for (std::size_t j = 0; j < M; ++j) s += splash.density(v[k], vix[j], viy[j]) * o.dv * x[j];
      next[k] = s, norm = std::max(norm, s);
    }
    if (norm <= 0) return 0;
    const double old = lambda;
    double xmax = 0;
    for (double e : x) xmax = std::max(xmax, e);
    lambda = norm / xmax;
    for (std::size_t k = 0; k < M; ++k) x[k] = next[k] / norm;
    if (it > 10 && std::abs(lambda - old) < 1e-10 * lambda) break;
  }
  return lambda;
}

double impact_threshold(WindModelOptions o, const SplashKernel& splash, double lo, double hi) {
  // Scan up from `lo` for the first growth >= 1, then bisect. (Far above threshold the growth falls again:
  // the rebounds leave faster than the launch grid reaches.)
  double below = lo;
  for (double u = lo; u <= hi; u *= 1.25) {
    o.u_star = u;
    if (clean_wind_growth(o, splash) >= 1) {
      double a = below, b = u;
      for (int i = 0; i < 40 && b / a > 1 + 1e-6; ++i) {
        o.u_star = std::sqrt(a * b);
        (clean_wind_growth(o, splash) < 1 ? a : b) = o.u_star;
      }
      return std::sqrt(a * b);
    }
    below = u;
  }
  return 0;
}

const std::vector<FluxLaw>& classic_flux_laws() {
  // D = 0.025 cm: Bagnold's and Lettau's reference grain. Threshold laws use the model's own u*_t.
  static const std::vector<FluxLaw> laws = {
      {"Bagnold 1941", "1.8 sqrt(d/D) rho/g u*^3",
       [](double u, double, double rho, double, double g, double d) {
         return 1.8 * std::sqrt(d / 0.025) * rho / g * u * u * u;
       }},
      {"Kawamura 1951", "2.78 rho/g (u* - u*t)(u* + u*t)^2",
       [](double u, double ut, double rho, double, double g, double) {
         return u <= ut ? 0.0 : 2.78 * rho / g * (u - ut) * (u + ut) * (u + ut);
       }},
      {"Lettau & Lettau 1978", "6.7 sqrt(d/D) rho/g u*^2 (u* - u*t)",
       [](double u, double ut, double rho, double, double g, double d) {
         return u <= ut ? 0.0 : 6.7 * std::sqrt(d / 0.025) * rho / g * u * u * (u - ut);
       }},
      {"Duran / Kok et al. 2012", "5 rho/g u*t (u*^2 - u*t^2)",
       [](double u, double ut, double rho, double, double g, double) {
         return u <= ut ? 0.0 : 5 * rho / g * ut * (u * u - ut * ut);
       }},
      {"Pahtz & Duran 2020",
       "rho_p d sqrt((s - 1) g d) 2 sqrt(Th_t)/(kappa mu_b) (Th - Th_t)(1 + c_M (Th - Th_t)/mu_b), "
       "kappa 0.4, mu_b 0.63, c_M 1.7",
       [](double u, double ut, double rho, double rhop, double g, double d) {
         const double s = rhop / rho, shields = rho * u * u / ((rhop - rho) * g * d),
                      shields_t = rho * ut * ut / ((rhop - rho) * g * d);
         const double q = fluid::transport_law_mass(shields, shields_t, 0.63) *
                          fluid::transport_law_velocity(shields, shields_t, 0.4, 0.63, 1.7);
         // Q* = Q / (rho_p d sqrt(s g^ d)) with g^ = (1 - 1/s) g, as Huo et al. (2021) state the law (their
         // eq. 31, quoting these coefficients) and as pydune implements it (docs/saltation.md).
         return q * rhop * d * std::sqrt((s - 1) * g * d);
       }},
  };
  return laws;
}

FluxGrowth flux_growth(const std::vector<double>& u_star, const std::vector<double>& q) {
  const std::size_t n = u_star.size();
  if (n < 3 || q.size() != n) throw std::invalid_argument("flux_growth needs three or more (u*, Q) points");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double x = std::log(u_star[k]), y = std::log(std::max(q[k], 1e-300));
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  // The secant slope of f against u*^2 between points a and b.
  auto slope = [&](auto f, std::size_t a, std::size_t b) {
    return (f(b) - f(a)) / (u_star[b] * u_star[b] - u_star[a] * u_star[a]);
  };
  auto ratio = [&](auto f) { return slope(f, n - 2, n - 1) / slope(f, 0, 1); };
  FluxGrowth g;
  g.exponent = (double(n) * sxy - sx * sy) / (double(n) * sxx - sx * sx);
  g.square_slope_ratio = ratio([&](std::size_t k) { return q[k]; });
  g.cube_slope_ratio = ratio([&](std::size_t k) { return u_star[k] * u_star[k] * u_star[k]; });
  return g;
}

}  // namespace grainlab::saltation
