#pragma once
// The thesis's continuum surface evolution (Ch. V section 1, eqs 5.3-5.8): surface grains move only by
// reptation, R = a F_beta, with the impact flux on a slope beta (eq. 5.6)
//   F_beta = F_x [1 + tan(beta) / tan(alpha)] / sqrt(1 + tan^2 beta),
// and the bed follows dh/dt = -d^2 dR/dx (eq. 5.4). Linearised, this is an anti-diffusion equation,
// dh/dt = -(a d^2 F_x / tan alpha) d2h/dx2: every undulation grows, the short ones fastest.
#include <vector>

namespace grainlab::ripples {

struct ContinuumParams {
  double F_x = 5;                   // impacts per cm^2 per s on a flat bed
  double a = 4;                     // reptation distance per impact, cm
  double d = 0.1;                   // effective grain diameter, cm
  double alpha_deg = 10;            // impact angle
  double dx = 0.5;                  // cm
  double dt = 1e-3;                 // s (explicit Euler)
  double anti_diffusivity() const;  // a d^2 F_x / tan(alpha), cm^2/s
};

// Eq. 5.6 per unit flat-bed flux, for a surface slope dh/dx (beta = atan(dh/dx)).
double impact_flux_on_slope(double slope, double alpha_deg);

// Advances a periodic profile h (cm, spacing dx) by `steps` explicit steps of eqs 5.3 and 5.6.
void advance_continuum(const ContinuumParams& p, std::vector<double>& h, int steps);

// The growth factor per step of a small sine of wavenumber k under the discrete scheme:
// 1 + dt D (2 - 2 cos(k dx)) / dx^2.
double continuum_growth_per_step(const ContinuumParams& p, double k);

// Steady propagation (eqs 5.5, 5.7, 5.8). A shape h(s), s = x - v t, moving unchanged at speed v needs
// v h = d^2 R + const (5.5); with R = a F_beta linear in the slope this is
//   dh/ds = (h - h0) / lambda - tan(alpha),  lambda = a d^2 F_x / (v tan alpha)          (5.7)
// whose solutions are flat (h = h0 + lambda tan alpha) or steepen exponentially:
//   h(s) = C exp(s / lambda) + lambda tan(alpha) + h0                                   (5.8)
double steady_length(const ContinuumParams& p, double v);
double steady_shape(const ContinuumParams& p, double v, double C, double h0, double s);
// Eq. 5.7 integrated by RK4 from h(s0) = h_start in n steps of ds: the numerical check on eq. 5.8.
std::vector<double> integrate_steady_shape(const ContinuumParams& p, double v, double h0, double h_start,
                                           double ds, int n);

}  // namespace grainlab::ripples
