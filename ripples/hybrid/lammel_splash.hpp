#pragma once
// The statistical splash of Lammel et al. (2017) as the 3-D hybrid ripple model uses it (Huo et al. 2021,
// eqs 8-15; reconstructed in spec frontiers-3d-ripples.md): the mean rebound restitution, the rebound
// angle distribution, and the number and energies of ejecta, all in the frame of the local bed. Three
// parameter sets: "paper2021" (the seed's reading: eps 0.9, mu 0, eta = m1/m2, 6 % of the energy the
// rebound does not keep goes to ejecta), "paper2021-effective" (the same with the effective mass ratio
// eta = eps d1^3 / (d1^3 + eps d2^3), the other eta convention in use) and "lammel2017" (eps 0.73,
// tangential nu = -0.18 in place of mu, the effective eta, 5 %). docs/hybrid.md says which a run used.
#include <string>
#include <vector>

#include "rng.hpp"

namespace grainlab::ripples::hybrid {

struct LammelParameters {
  std::string name = "paper2021";
  double restitution = 0.9;       // eps
  double tangential = 0.0;        // mu (or Lammel's nu) in beta_L = 1 - (2/7)(1 - mu)/(1 + eta)
  bool effective_eta = false;     // eta = eps d1^3/(d1^3 + eps d2^3) instead of m1/m2 = d1^3/d2^3
  double ejecta_fraction = 0.06;  // of (1 - e^2) E1, given to ejecta (the 0.06 of eq. 15)
  static LammelParameters paper2021();
  static LammelParameters paper2021_effective();
  static LammelParameters lammel2017();
  // The sets' names, and whether `name` is one of them (otherwise it names a recorded splash file).
  static const std::vector<std::string>& names();
  static bool is_named(const std::string& name);
  static std::string names_quoted();  // "paper2021", ... for messages
  // By name; throws std::invalid_argument naming the known sets.
  static LammelParameters named(const std::string& name);
};

// The impact's coefficients for impactor diameter d1 on a bed grain d2.
struct LammelCoefficients {
  double eta, alpha, beta, gamma;  // alpha_L, beta_L and gamma of eqs 8-10
};
LammelCoefficients lammel_coefficients(const LammelParameters& p, double d1, double d2);

// Mean rebound restitution (eq. 8) at impact angle theta (rad, below the bed plane).
double mean_restitution(const LammelCoefficients& c, double d1, double d2, double theta);
// Rebound angle theta' (rad above the bed plane) for a uniform number u in [0, 1), by inverting the CDF of
// eq. 9, F = s (1 - ln s) with s = (theta' + theta)^2 gamma / (2 theta).
double rebound_angle(const LammelCoefficients& c, double theta, double u);
// The mean of eq. 9: (4 sqrt 2 / 9) sqrt(theta / gamma) - theta.
double mean_rebound_angle(const LammelCoefficients& c, double theta);

// Ejecta of an impact with energy e1 when a bed grain needs e_d2 (m2 g d2, or the wind-loosened E_eff) to
// leave: the energy E2 of each candidate is lognormal (mu_e, sigma) and only those above e_d2 leave.
struct EjectaLaw {
  double mean_count = 0;  // N of eq. 15
  double mu_e = 0, sigma = 0, e_d2 = 0;
  double escape_probability = 0;  // P(E2 > e_d2)
  double mean_energy() const;     // of the ejecta that leave: E[E2 | E2 > e_d2]
};
EjectaLaw ejecta_law(const LammelParameters& p, double e_bar, double e1, double e_d2);
// A draw: the number of ejecta (stochastic rounding of mean_count) and an energy above e_d2 for one.
int sample_ejecta_count(const EjectaLaw& law, Rng& rng);
// x with P(Z > x) = q for the standard normal Z, to round-off (the ejecta energies' inverse CDF).
double normal_tail_quantile(double q);
double sample_ejectum_energy(const EjectaLaw& law, Rng& rng);

}  // namespace grainlab::ripples::hybrid
