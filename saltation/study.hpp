#pragma once
// Beyond the thesis: the wind-driven model on other planets and grain sizes, its impact threshold, and the
// classic flux laws to compare it with.
#include <functional>
#include <string>
#include <vector>

#include "wind_model.hpp"

namespace grainlab::saltation {

struct Planet {
  std::string name;
  double g = 981;                // cm/s^2
  double air_density = 0.00123;  // g/cm^3
  double viscosity = 0.146;      // kinematic, cm^2/s
};
// earth (the thesis's air), mars (CO2 at ~0.02 kg/m^3, ~210 K), venus (CO2 at ~65 kg/m^3, ~735 K); throws
// std::invalid_argument for other names.
Planet planet_preset(const std::string& name);
std::vector<std::string> planet_names();

// Eq. 4.34's constants for grains whose velocity scale sqrt(g d) is `s` times the thesis's (0.025 cm sand on
// Earth): speeds c2, c4, c5 scale by s and c3 by 1/s^3, so every number of grains per impact is kept at the
// same v / sqrt(g d). The same scaling the model applies to a splash file.
AnalyticSplash scaled(const AnalyticSplash& a, double s);

// The largest eigenvalue of [T] in the wind without grains at `o.u_star`: grains launched per grain
// launched. Saltation sustains itself where it exceeds 1.
double clean_wind_growth(const WindModelOptions& o, const SplashKernel& splash);
// The impact threshold u*_t: the lowest u* where the clean-wind growth reaches 1 (a scan up from `lo`, then
// bisection), i.e. where the steady state's flux goes to zero. Returns 0 if it stays below 1 up to `hi`.
double impact_threshold(WindModelOptions o, const SplashKernel& splash, double lo = 1, double hi = 2000);

// A flux law Q(u*) in g/(cm s) for air density rho, grain density rho_p, g, grain diameter d (cgs) and the
// threshold u*_t the model found.
struct FluxLaw {
  std::string name, formula;
  std::function<double(double u_star, double u_t, double rho, double rho_p, double g, double d)> q;
};
// Bagnold (1941), Kawamura (1951), Lettau & Lettau (1978), Duran / Kok et al. (2012), Pahtz & Duran (2020),
// each with its published coefficients (docs/saltation.md).
const std::vector<FluxLaw>& classic_flux_laws();

// How a flux grows with u*, from three or more (u*, Q) points in rising u*. `exponent`: the least-squares n
// of Q ~ u*^n on log axes. `square_slope_ratio`: the slope dQ / d(u*^2) between the last two points over
// that between the first two; it is 1 whenever Q is linear in u*^2, with or without a threshold (Ungar &
// Haff's Q ~ u*^2 - u*_t^2, which the thesis cites), while a threshold makes `exponent` run far above 2
// near it. `cube_slope_ratio`: the same ratio for Q ~ u*^3 at the same u*, the other law the thesis names.
struct FluxGrowth {
  double exponent = 0, square_slope_ratio = 0, cube_slope_ratio = 0;
};
FluxGrowth flux_growth(const std::vector<double>& u_star, const std::vector<double>& q);

}  // namespace grainlab::saltation
