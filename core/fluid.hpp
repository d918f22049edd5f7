#pragma once
// The fluid physics shared by the steady-state saltation model (saltation/) and the engine's wind_drag
// effect (native_dem/wind.*): drag laws for a sphere, and the horizontally averaged wind over a bed
// whose shear stress the grains reduce (the thesis's eqs 4.27-4.28; the van Driest form of Huo et al.
// 2021). Pure functions; units cgs.
#include <vector>

#include "scene.hpp"

namespace grainlab::fluid {

// Drag coefficient of a sphere at Reynolds number re = d |v_rel| / nu.
// Thesis (eq. 4.31): 24/Re + 6/(1 + sqrt(Re)) + 0.4. Dalla Valle: (0.63 + 4.8/sqrt(Re))^2. Huo et al.
// 2021: (sqrt(0.5) + sqrt(24/Re))^2.
double drag_coefficient(WindSpec::DragLaw law, double re);

// The acceleration drag gives a sphere of diameter d and density rho_grain moving at v_rel relative to
// the fluid, as a factor c: a = -c v_rel (eq. 4.30 divided by the sphere's mass).
double drag_rate(WindSpec::DragLaw law, const FluidSpec& f, double diameter, double speed_rel);

struct WindProfileInput {
  WindSpec::Model model = WindSpec::Model::MixingLength;
  double kappa = 0.4;
  double roughness = 0;  // z0, cm: u = 0 at z <= z0
  double viscosity = 0;  // cm^2/s (the viscous term of the van Driest model)
  double u_star = 0;     // shear velocity of the clean wind (van Driest damping length 26 nu / u*)
};

// Wind speed at heights z (cm above the bed, ascending) given the kinematic fluid shear stress
// tau_f / rho at those heights (cm^2/s^2, negative read as 0). u(z0) = 0; between heights the slope
// solves l^2 (du/dz)^2 + nu_eff du/dz = tau/rho with l = kappa z (thesis: nu_eff = 0, so du/dz =
// sqrt(tau/rho)/(kappa z)) or l = kappa z (1 - exp(-z u*/(26 nu))) and nu_eff = nu (van Driest),
// integrated in log z so the log law is exact for constant stress. z0 = 0 is a smooth wall (van Driest
// only: the first height should then lie in the viscous sublayer, z u* / nu << 1).
std::vector<double> wind_profile(const WindProfileInput& in, const std::vector<double>& z,
                                 const std::vector<double>& stress);

// One backward-Euler step dt of the horizontally averaged wind over a column of cells of height dz
// (centres z above the bed, ascending; cells at z <= z0 are held at u = 0):
//   du/dt = d/dz (nu_eff du/dz) - (a u - b),   nu_eff = l^2 |du/dz| (+ nu for van Driest),
// with the kinematic stress u*^2 entering through the top face. a (1/s) and b (cm/s^2) are the grains'
// drag in the cell linearised in u (sum of m c over rho_f times the cell volume, and the same times the
// grains' velocities), so the grains' answer to the wind is implicit and the step is stable for any dt.
// `eddy` holds the faces' eddy viscosity l^2 |du/dz| the step uses (filled from u when empty) and leaves
// the next step's: the geometric mean of the used one and the new profile's, a damped fixed point
// (docs/saltation.md). dt = infinity gives the steady profile for this drag.
std::vector<double> advance_wind_column(const WindProfileInput& in, double dz, const std::vector<double>& z,
                                        const std::vector<double>& u, const std::vector<double>& a,
                                        const std::vector<double>& b, double dt, std::vector<double>& eddy);
// The conductance G of the face between cells k and k + 1 for the profile u: its kinematic stress is
// G (u[k+1] - u[k]) / dz (eddy part exact for the log law; the face onto the bed starts at z0).
double face_conductance(const WindProfileInput& in, double dz, const std::vector<double>& z,
                        const std::vector<double>& u, std::size_t k);
// The kinematic fluid stress on the face between cells k and k + 1.
double face_stress(const WindProfileInput& in, double dz, const std::vector<double>& z,
                   const std::vector<double>& u, std::size_t k);

// Pahtz & Duran's (2020) transport law, as Huo et al. (2021) state it (their eq. 31): Q* = M* v* with the
// airborne mass per bed area M* = (S - S_d) / mu_b (over rho_p d) and the transport velocity v* = (2
// sqrt(S_d) / kappa)(1 + (c_M / mu_b)(S - S_d)) (over sqrt(s g^ d), g^ = (1 - 1/s) g); S the Shields
// number, S_d its threshold. Both are zero below S_d. Pahtz & Duran give kappa 0.4, mu_b 0.63, c_M 1.7;
// Huo et al. fit 0.61 and 2.3 with kappa 0.42.
double transport_law_mass(double shields, double shields_threshold, double mu_b);
double transport_law_velocity(double shields, double shields_threshold, double kappa, double mu_b,
                              double c_m);

}  // namespace grainlab::fluid
