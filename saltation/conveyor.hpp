#pragma once
// The thesis's conveyor-belt feedback model (Ch. IV section 1): a belt at height h, driven with power
// P_T per area against friction zeta v_c^2, carries grains launched from the bed; the bed splashes them
// back up. The delta-function splash has a closed form (eqs 4.3-4.5) and a time-dependent map (4.23) with
// its linearisation (4.24-4.26); the velocity-distribution splash (4.12-4.16) is a fixed point of the
// belt-convolved kernel on a grid of launch velocities. Pure functions over plain structs; every iteration
// returns its history so convergence can be plotted and tested.
#include <complex>
#include <string>
#include <vector>

namespace grainlab::saltation {

// ---- delta-function splash (Ungar & Haff 1986): v_box = 0, v_boy = (-eps v_biy + f v_bix) / sqrt(N) ----

struct DeltaSteadyState {
  bool transport = false;  // false below threshold (P_T <= zeta v_c^2) or when f <= 1 - eps^2
  double v_bix = 0, v_biy = 0, v_boy = 0, v_c = 0;
  double F = 0;    // launched grains per area per time
  double P_g = 0;  // power given to the grains
};
// Eqs 4.3-4.5.
DeltaSteadyState conveyor_delta_steady(double f, double eps, double v_g, double P_T, double zeta);

struct ConveyorMapParams {
  double f_max = 0.8, f_min = 0.8;  // f falls linearly from f_max to f_min as the impact speed v_bix
  double f_v1 = 1.0, f_v2 = 2.0;    // rises from f_v1 to f_v2 (Table 4.2 E; its law is not given)
  double eps = 0.6, P_T = 1000, zeta = 0, v_g = 1;
  // Eq. 4.23 does not say whether v_c is solved before or after v_oy moves: "simultaneous" updates F and
  // v_oy from step n and then solves v_c; "velocity-first" moves v_oy, solves v_c, then updates F with N
  // from the new state.
  std::string order = "simultaneous";
  double f_at(double v_bix) const;
};

struct MapState {
  double F = 0, v_oy = 0, v_c = 0, N = 0;
};

struct ConveyorMapResult {
  std::vector<MapState> history;  // from the start
  bool converged = false;
  int iterations = 0;
  std::vector<double> residuals;  // largest relative change of F, v_oy, v_c per step
};
// Table 4.2: CASE D (f = 0.8 throughout) and E (f falls from 0.8 to 0.6 as the impact speed rises; the
// thesis gives no law: grainlab's falls linearly over 0.15 v_g, placed so that the fixed point sits at the
// thesis's (F, v_oy) ~ (20, 1)). Throws std::invalid_argument for another name.
ConveyorMapParams table_4_2(const std::string& case_name);
// Iterates eq. 4.23 from (F0, v_oy0) until every variable changes by less than `tol` relatively.
ConveyorMapResult conveyor_map(const ConveyorMapParams& p, double F0, double v_oy0,
                               int max_iterations = 10000, double tol = 1e-12);
// The belt speed that spends P_T on flux F launched at v_oy: P_T = F v_c (v_c v_oy / (v_c + v_oy)) + zeta
// v_c^2.
double belt_speed_for_map(const ConveyorMapParams& p, double F, double v_oy);

struct ConveyorLinearization {
  double jacobian[2][2] = {{0, 0}, {0, 0}};  // d(v_oy, F)(n+1) / d(v_oy, F)(n) at the fixed point, v_c solved
  std::complex<double> eigenvalues[2];
  // Eq. 4.26's entries (per unit h; the time per iteration is h (eps + 1) / (eps v_oy)).
  double A11 = 0, B11 = 0, B12 = 0, B22 = 0;
};
ConveyorLinearization conveyor_linearization(const ConveyorMapParams& p, const MapState& fixed_point);

// ---- velocity-distribution splash (eq. 4.12) ----

struct DistributionSplashParams {
  double f = 0.8, eps = 0.6, alpha = 1.6, beta = 0.5, gamma = 0, delta = 1, e5 = 3.0;
  double P_T = 1000, zeta = 0.05;
  int bins = 40;      // M
  double dmu = 0.25;  // bin width; mu_j = (j - 1/2) dmu
};
// Table 4.1's CASES A, B, C (throws std::invalid_argument for another name).
DistributionSplashParams table_4_1(const std::string& case_name);

// The belt-convolved kernel T(v, v'; v_c) of eq. 4.13: grains launched at v per grain launched at v'.
double conveyor_kernel(const DistributionSplashParams& p, double v, double v_prime, double v_c);

struct DistributionResult {
  std::vector<double> mu, F;  // bin centres and the steady launch-velocity distribution
  double v_c = 0;
  bool converged = false;
  int iterations = 0;
  std::vector<double> residuals;  // largest relative change of F (over its maximum) and v_c per step
  std::string failure;            // why it did not converge (the flux died out, or the iteration limit)
};
// F(n+1) = [T{v_c(F(n))}] F(n) (eq. 4.16) from a flat start (or `start`, one value per bin), v_c solved
// from the power balance P_T = v_c sum_i F_i [v_c mu_i / (mu_i + v_c)] dmu + zeta v_c^2 at every step.
// A start that sends the flux to zero (F = 0 is a fixed point too) is reported in `failure`, not as
// converged.
DistributionResult conveyor_distribution(const DistributionSplashParams& p, int max_iterations = 5000,
                                         double tol = 1e-10, const std::vector<double>& start = {});

}  // namespace grainlab::saltation
