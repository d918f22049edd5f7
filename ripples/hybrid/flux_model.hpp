#pragma once
// The 3-D hybrid model's transport over a fixed flat bed (Huo et al. 2021, section 3.1's flux runs):
// airborne grains tracked one by one (drag of the huo2021 law, gravity with buoyancy, Heun steps),
// mid-air collisions found in a column grid, the Lammel splash where a grain reaches the bed, and a
// steady 1-D wind (van Driest mixing length, kappa 0.42) whose stress the grains' drag takes up. The bed
// never changes: an unlimited supply of grains to eject, and grains that land dead are gone. What it
// measures is the saturated flux Q* against the Shields number S, the law the paper fits (eq. 31).
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "transport.hpp"

namespace grainlab::ripples::hybrid {

struct FluxOptions : TransportOptions {
  double duration = 4000, average_from = 2000;   // t* = t / sqrt(d / g^)
  std::function<void(double, double)> progress;  // (t*, duration)
  // Checkpoints: every checkpoint_every t* (0: never), at stop_at and at the end, `checkpoint` is handed
  // the run's whole state as tables (flux_checkpoint_columns names them); a run given such a state in
  // `restart` continues from it to the same bits as a run never stopped. stop_at > 0 ends the run at the
  // first sample at or after that t*, its result marked `stopped`.
  double checkpoint_every = 0, stop_at = 0;
  std::function<void(const std::vector<SampleTable>&)> checkpoint;
  const std::map<std::string, SampleTable>* restart = nullptr;
};

struct FluxResult {
  double s = 0, galileo = 0,
         shields = 0;  // s = rho_p / rho_f, Ga = sqrt(s g^ d^3)/nu, S = rho_f u*^2/(rho_p g^ d)
  double mass_flux = 0, mass_flux_star = 0;  // window means: g/(cm s) and Q / (rho_p d sqrt(s g^ d))
  double mass_flux_sd = 0;                   // of the window's samples (one per t*)
  double airborne = 0;                       // grains in flight, window mean
  double airborne_mass_star = 0;             // their mass per bed area over rho_p d (M* of eq. 31's balance)
  double u_star_bed = 0;                     // sqrt(tau_f / rho_f) at the bed
  double impacts_per_area_time = 0;          // 1/(cm^2 s)
  double mean_impact_speed = 0, mean_impact_angle_deg = 0;
  // mu_b of eq. 31, measured: the downwind over the downward momentum the bed takes in the window. The
  // law's flux near threshold goes as 1 / mu_b (the paper fits 0.61).
  double bed_friction = 0;
  std::vector<double> z, u, u_clean;          // the wind at the end (cm, cm/s)
  std::vector<double> u_mean;                 // the wind at z, mean over the window's samples (cm/s)
  std::vector<std::array<double, 3>> series;  // t*, Q*, airborne
  std::uint64_t grain_steps = 0, steps = 0, collisions = 0;
  std::uint64_t fast_collisions = 0;  // of those, by the fast_substeps pass
  double wall_seconds = 0;            // all segments of a run continued from checkpoints
  double t_star = 0;                  // where it ended
  bool stopped = false;               // at stop_at, before the duration
};

// The tables (name -> columns) of a flux run's checkpoint with these options, to read one back.
std::map<std::string, std::vector<std::string>> flux_checkpoint_columns(const FluxOptions& o);

// Throws std::invalid_argument for options that cannot run (non-positive sizes, unknown splash set).
FluxResult run_flux(const FluxOptions& o);

// The grain-free wind of the flux run's column: heights (cm) and speeds (cm/s).
struct CleanWind {
  std::vector<double> z, u;
};
CleanWind clean_wind(const FluxOptions& o);

// Eq. 31 (Pahtz & Duran 2020 form): Q* = (2 sqrt(S_d) / (kappa mu_b)) (S - S_d) [1 + (c_M / mu_b)(S - S_d)],
// with the paper's constants. It is the product of an airborne mass per bed area (over rho_p d), M* = (S -
// S_d) / mu_b, and a transport velocity (over sqrt(s g^ d)), v* = (2 sqrt(S_d) / kappa)(1 + (c_M / mu_b)(S
// - S_d)); both are zero below S_d.
inline constexpr double kLawKappa = 0.42, kLawBedFriction = 0.61, kLawCM = 2.3;
double flux_law_mass(double shields, double shields_threshold, double mu_b = kLawBedFriction);
double flux_law_velocity(double shields, double shields_threshold, double kappa = kLawKappa,
                         double mu_b = kLawBedFriction, double c_m = kLawCM);
double flux_law(double shields, double shields_threshold, double kappa = kLawKappa,
                double mu_b = kLawBedFriction, double c_m = kLawCM);

}  // namespace grainlab::ripples::hybrid
