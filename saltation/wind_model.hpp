#pragma once
// The thesis's steady-state saltation model with wind (Ch. IV section 2, algorithm of Fig. 4.10): grains
// launched from a flat bed fly through a mixing-length wind under gravity and drag (eqs 4.30-4.31); their
// drag slows the wind (eq. 4.27 in quadrature form); on landing each one splashes grains back up (the
// splash function of eq. 4.34). The launch-velocity distribution F is the fixed point F = [T{u}] F.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "splash_file.hpp"

namespace grainlab::saltation {

struct Fluid {
  double density = 0.00123;  // g/cm^3
  double viscosity = 0.146;  // kinematic, cm^2/s
  double k = 2.5;            // the thesis's "von Karman constant" = 1 / 0.4
};

struct Grain {
  double radius = 0.0125;  // cm
  double density = 2.6;    // g/cm^3
  double mass() const;
};

// Eq. 4.34 with Table 4.3's constants (c2, c4, c5 in cm/s).
struct AnalyticSplash {
  double c1 = 2, c2 = 35, c3 = 0, c4 = 40, c5 = 275, c6 = 0, eps = 0.7, f = 0.1;
  // Grains launched per unit vertical velocity by one impact (v_ix > 0, v_iy < 0).
  double density(double v_oy, double v_ix, double v_iy) const;
  // Their common horizontal launch velocity.
  double launch_vx(double v_ix) const { return c6 * eps * (1 - f) * v_ix; }
};
// Table 4.3 CASES 1-6 (throws std::invalid_argument otherwise) and the u* the thesis ran each at.
AnalyticSplash table_4_3(int case_number);
std::array<double, 3> table_4_3_ustars(int case_number);

struct WindModelOptions {
  Fluid fluid;
  Grain grain;
  double g = 981;
  bool buoyancy = false;  // gravity reduced by (1 - rho_air / rho_grain): off in the thesis, 2.5 % on Venus
  double u_star = 35;     // cm/s, above the saltation layer
  double dv = 5;          // launch-velocity bin (cm/s); bins centred at (j + 1/2) dv
  int bins = 80;
  int heights = 240;  // wind grid: log-spaced from the roughness length to `top`
  double top = 2000;  // cm
  double tolerance =
      1e-3;  // converged when no F component (over max F) and no u(y) changes more than this (the
             // thesis used 1e-2: u*_eff^2 is a small difference of large numbers, see docs)
  int max_iterations = 400;
  double relaxation = 0.5;  // under-relaxation of the wind update (1: none); halved while it oscillates
  // Re = reynolds_factor x 2 r |v_rel| / nu in eq. 4.31. 1 is the equation as printed; 2 (the diameter
  // where the radius stands) brings Table 4.5 and the Ch. IV text numbers much closer (docs/saltation.md).
  double reynolds_factor = 1;
  double flux_damping = 0.5;  // F(n+1) = (1 - b) F(n) + b [T] F(n): damps the flux-wind overshoot
  // The thesis averaged the grains' drag on the air "over a vertical distance of the order of the spacing
  // of trajectory heights" without giving the kernel. > 0: each height bin's drag is spread evenly over
  // this many cm around it (kept above the bed) before the wind sees it; the total is unchanged, so the
  // identities hold. 0: the drag where the grains take it.
  double drag_smoothing = 0;
  // Launches slower than this (cm/s, vertical) do not leave the bed: their bins get no grains. 0 (the
  // default): every bin of eq. 4.34 fills. A reading test for the thesis's number density, which peaks
  // about 0.5 cm off the bed (the apex of a 31 cm/s launch), where eq. 4.34's slow launches put it at the
  // bed (docs/saltation.md, "Slow launches").
  double launch_min = 0;
  // A splash file with moments only (the sand gun, 650-1200 cm/s): how its ejecta number is carried below
  // the slowest measured impact. line: the cells' least-squares line in impact speed, zero below its root
  // (about 300 cm/s for the sand gun); proportional: from the line's value at the slowest cell, in
  // proportion to the impact speed down to zero. The thesis "extrapolated outside" the range without
  // saying how; its CASE 7 lies between the two (docs/saltation.md).
  enum class EjectaBelowRange { line, proportional };
  EjectaBelowRange ejecta_below_range = EjectaBelowRange::line;
  int profile_subdivisions = 16;
  // Each flight is integrated by Dormand-Prince 5(4) to this error per step, relative (and absolute in
  // grain diameters and sqrt(g d)), and its path is sampled for the height bins every sample_interval s.
  double trajectory_tolerance = 1e-8;
  double sample_interval = 5e-4;
  // A 2-D launch grid (v_oy bins x vx_bins values of v_ox, dv apart from vx_min): every state keeps its
  // own v_ox. 0: the thesis's 1-D grid, where a bin's v_ox is the mean of the impacts that feed it.
  int vx_bins = 0;
  // The starting F per launch bin (grains per cm^2 per s per cm/s; with a 2-D grid, in the v_ox = 0
  // column). Empty: a weak, broad start, exp(-v / 100 cm/s) / 100.
  std::vector<double> start;
  double vx_min = -100;                                   // cm/s
  double roughness() const { return grain.radius / 15; }  // l = d/30
};

struct Trajectory {
  double v_ox = 0, v_oy = 0;  // launch
  double v_ix = 0, v_iy = 0;  // at landing
  double length = 0, height = 0, time = 0;
  int steps = 0;  // accepted integrator steps
};

// Mean, standard deviation and half width at half maximum of a distribution F over bin centres v (the
// half maximum's crossings interpolated linearly between bins; a side that never falls below it counts
// from the grid's end). The thesis calls its Gaussian's sigma (c2) the "intrinsic half-width", so both
// readings of its "half-width" are kept.
struct LaunchSpread {
  double mean = 0, sd = 0, half_width = 0;
};
LaunchSpread launch_spread(const std::vector<double>& v, const std::vector<double>& F);

struct WindModelResult {
  bool converged = false;
  std::string failure;              // why there is no steady state, when there is none
  int iterations = 0;               // outer iterations (F updates)
  int trajectory_passes = 0;        // inner wind-trajectory passes in all
  std::vector<double> residuals;    // largest relative change of F or u per outer iteration
  std::vector<double> v_launch, F;  // bin centres (cm/s) and F (grains per cm^2 per s per cm/s)
  std::vector<double> v_ox;         // the horizontal launch velocity of each bin
  std::vector<Trajectory> trajectories;
  std::vector<double> F2d;            // 2-D grid only: F per (v_oy bin, v_ox cell), row-major in v_oy
  std::vector<double> y, u, u_clean;  // wind with and without grains (cm/s)
  std::vector<double> dy;             // height of the bin around each y (cm): profile x dy sums to a total
  std::vector<double> drag;           // force per unit volume the grains take from the air, at y (dyn/cm^3)
  std::vector<double> tau;            // fluid shear stress at y (dyn/cm^2)
  // Per height (per unit volume): grains per cm^3, horizontal number flux (grains / cm^2 / s) and the
  // kinetic-energy flux (erg / cm^3, see FlightProfiles).
  // drag_resolved: the drag profile from the same sub-launches (the wind itself sees `drag`, whose apex
  // spikes the thesis smoothed over the spacing of trajectory heights).
  std::vector<double> number_density, number_flux, energy_flux, drag_resolved;
  double u_star_eff = 0;                            // sqrt(tau at the bed / rho)
  double grain_stress = 0;                          // tau_g: the momentum flux the grains carry (dyn/cm^2)
  double mass_flux = 0;                             // Q, g/(cm s)
  double launch_rate = 0;                           // grains per cm^2 per s
  double mean_hop_height = 0, mean_hop_length = 0;  // launch-weighted (cm)
  // The same means over the grains in the air at an instant (each hop weighted by its launch rate times
  // its flight time): what a snapshot of the saltation layer shows.
  double airborne_hop_height = 0, airborne_hop_length = 0;
  double mean_impact_vx = 0, mean_impact_vy = 0;  // launch-weighted (cm/s)
  // The same four quantities' standard deviations over the hops (launch-weighted). Of these the thesis
  // writes, for CASE 1, that "in going from u* = 35 to 125 cm/sec, the half-widths of the distributions of
  // these quantities increase by ten to thirty percent" (its half-width is a sigma, as for c2).
  double sd_hop_height = 0, sd_hop_length = 0, sd_impact_vx = 0, sd_impact_vy = 0;
  // The spread of the launch distribution F(v_oy) (summed over v_ox), which the thesis describes for
  // CASE 1 (Fig. 4.11: "half-widths of about 45 cm/sec").
  LaunchSpread launch_vy;
  double wall_seconds = 0;
  long flight_steps = 0, flights = 0;  // the final pass's integrator steps and flights
};

// The model's heights: nodes log-spaced from the roughness length to `top`, and the edges of the bins
// around them (from 0 below the first node to far above the last).
std::vector<double> height_nodes(const WindModelOptions& o);
std::vector<double> bin_edges(const std::vector<double>& y);
// The wind over grains whose drag takes impulse[k] (dyn/cm^2 per s: force per area) from the air in
// height bin k: the stress falls from rho u*^2 above by each bin's take (eq. 4.27 in quadrature; tau_edge
// at each bin's lower edge, H + 1 values) and u integrates du / d(ln y) = k sqrt(tau / rho) from zero
// at the first node.
void wind_from_drag(const WindModelOptions& o, const std::vector<double>& y,
                    const std::vector<double>& impulse, std::vector<double>& u,
                    std::vector<double>& tau_edge);

// The wind u(y) on the model's grid: zero below the roughness length, the log law above the grid.
double wind_at(const WindModelOptions& o, const std::vector<double>& y, const std::vector<double>& u,
               double h);
// What a flight leaves in each height bin, weighted by its launch rate: grain-seconds (number density once
// divided by the bin's height), grain-seconds x v_x (horizontal number flux) and x m v_x^2 / 2 (the
// thesis's kinetic-energy flux: "the number density times the square of the horizontal velocity").
struct FlightProfiles {
  std::vector<double> time, number_flux, energy_flux;
  explicit FlightProfiles(std::size_t bins) : time(bins), number_flux(bins), energy_flux(bins) {}
};
// One grain from the bed at (v_ox, v_oy) through the wind until it lands. If `impulse` is given, the
// horizontal momentum the drag gives it is added per height bin (bin edges `edges`, weight `weight`);
// if `profiles` is given, so is its share of them.
Trajectory fly(const WindModelOptions& o, const std::vector<double>& y, const std::vector<double>& u,
               double v_ox, double v_oy, const std::vector<double>* edges = nullptr,
               std::vector<double>* impulse = nullptr, double weight = 0, FlightProfiles* profiles = nullptr);

// A splash function as the model uses it: grains launched per unit vertical velocity (cm/s) by one impact
// at (v_ix, v_iy) (cm/s, v_iy < 0), and the horizontal velocity they leave with.
struct SplashKernel {
  std::function<double(double v_oy, double v_ix, double v_iy)> density;
  std::function<double(double v_ix, double v_iy)> launch_vx;
  // Grains per impact launched above the top of the model's launch grid, which the model loses. Set by
  // kernels that bin their launches on that grid; otherwise the density is integrated above the top.
  std::function<double(double v_ix, double v_iy)> above_grid = nullptr;
};
SplashKernel kernel_of(const AnalyticSplash& s);
// A grainlab-splash/1 file scaled to grains of the model's diameter (velocities x sqrt(g d)). Simulated
// files: each cell's rebound and ejecta launch velocities binned on the model's launch grid (per impact,
// per cm/s), interpolated bilinearly between the cells around an impact's speed and angle (held at the
// edge cells outside the grid). Measured files with moments only (the sand gun): the rebound as a Gaussian
// of the nearest cell's eps_iy x |v_iy|, ejecta numbering the cells' least-squares line in impact speed
// (below the slowest cell as o.ejecta_below_range says), launched with an exponential of the measured
// mean v_y.
SplashKernel kernel_of(const SplashFile& f, const WindModelOptions& o);

// Solves for the steady state (Fig. 4.10).
WindModelResult solve_wind_model(const WindModelOptions& o, const SplashKernel& splash);
// Height (cm) of a profile's largest value at or above `from` (the thesis's heights start a grain diameter
// up: below it the model's wind is not defined). Table 4.4 lists these for the flux, the kinetic-energy flux
// and the drag; the text gives the number density's for CASE 1.
double peak_height(const std::vector<double>& y, const std::vector<double>& v, double from);
inline WindModelResult solve_wind_model(const WindModelOptions& o, const AnalyticSplash& splash) {
  return solve_wind_model(o, kernel_of(splash));
}

// The thesis's "general model" in 2-D (Ch. VI): a recorded splash, scaled to the grains of `o` (velocities
// in sqrt(g d), as kernel_of), drives the steady wind of Fig. 4.10 at o.u_star, and the ejecta it records
// are flown through that wind instead of thrown ballistically. Each launch bin's grains land at their
// trajectory's impact velocity, at a rate F dv; that impact draws on the file's nearest cell, whose every
// ejectum counts with weight rate / (the cell's impacts). The hops (grain diameters, negative: upstream,
// each the flight's length to a flat bed) are resampled by those weights to `samples` values, so a model
// drawing uniformly from them draws from the steady state's ejecta. Throws std::invalid_argument when the
// wind has no steady state or no impact's cell holds recorded ejecta (a file with moments only).
struct WindBlownHops {
  std::vector<double> hops_d;
  double ballistic_mean_d = 0;  // the same weighted ejecta's mean ballistic range 2 v_x v_y
  double upstream_share = 0;    // weight of the hops that go upstream
  double impact_deg = 0;        // the impacts' mean angle below the horizontal, weighted by their ejecta
  double impact_speed = 0;      // and their mean speed, sqrt(g d)
  std::size_t ejecta_flown = 0, cells_used = 0;
  WindModelResult wind;
};
WindBlownHops wind_blown_hops(const SplashFile& f, const WindModelOptions& o, std::size_t samples = 4000);

}  // namespace grainlab::saltation
