#pragma once
// Saltation from first principles (issue #18): a periodic 2-D bed of sand grains under a wind that the
// grains slow down (effect wind_drag), run to a steady state, with the flux, hop statistics, impact and
// lift-off velocities, profiles and the splash measured from the grain dynamics alone, no splash function
// assumed. docs/saltation.md, "DEM saltation".
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ensemble.hpp"
#include "splash_file.hpp"
#include "wind_model.hpp"

namespace grainlab::validation {

struct DemSaltationOptions {
  double u_star = 40;              // cm/s
  double diameter = 0.025;         // cm, mean grain diameter
  double polydispersity = 0.15;    // radii uniform in mean (1 +- this)
  int columns = 400, layers = 12;  // lattice the bed falls from (spacing 1.2 d)
  double grain_density = 2.65, fluid_density = 0.00123, viscosity = 0.146;  // g/cm^3, cm^2/s
  double k_n = 2e5;  // dyn/cm (k_s = k_n / 2); reduced, as is standard
  double restitution = 0.9, mu = 0.5;
  // Saltation is started, not waited for: a sparse row of grains (one per 8 columns) is thrown from
  // 20 d above the bed at this speed downwind; a wind above the impact threshold keeps the flux going.
  double kick_speed = 100;        // cm/s; 0: none (the fluid must entrain grains itself)
  double steps_per_contact = 25;  // Verlet dt = contact time of two mean grains / this
  double duration = 2.0;          // s of physical time
  double average_from = 1.0;      // s: the steady-state window starts here
  double sample_interval = 1e-4;  // s between samples of every grain (flights, profiles)
  double splash_window = 0.01;    // s after an impact in which lift-offs nearby belong to it
  double splash_reach = 10;       // grain diameters from the impact point an ejectum may start
  double wind_update = 1e-4;      // s between wind updates
  // Neighbour-list skin, cm (0: the engine's default, a quarter of the smallest radius). Half a diameter:
  // saltating grains cross the default skin in ~10 steps and the rebuilds dominate (1.55x faster).
  double skin = 0.0125;
  std::uint64_t seed = 18;
  bool distributed = false;                      // spread the bed over the MPI ranks
  bool model_comparison = true;                  // run the Ch. IV model with the measured splash afterwards
  std::function<void(double, double)> progress;  // (t, duration)
  // Checkpoints (docs/saltation.md): the world and everything measured so far are written to
  // `checkpoint` every `checkpoint_every` s of physical time; `restart` continues from such a file to the
  // same result, bit for bit; `stop_at` (> 0) ends the run at that time right after its checkpoint.
  std::string checkpoint, restart;
  double checkpoint_every = 0.1, stop_at = 0;
};

// The scene the study runs (TOML text), ready for load_scene's parser.
std::string dem_saltation_scene(const DemSaltationOptions& o);

struct Crossing {  // a grain crossing one diameter above the bed, up (lift-off) or down (impact)
  double t, x, vx, vy;
  std::size_t grain;
};

struct DemSaltationResult {
  // Steady state (means over the window, intervals over 10 blocks of it).
  MeanInterval mass_flux;   // g/(cm s): sum of m v_x over the bed area's width and the slab thickness
  MeanInterval u_star_eff;  // cm/s: sqrt(tau_fluid / rho) at the bed
  MeanInterval airborne;    // grains more than one diameter above the bed
  double first_half_flux = 0, second_half_flux = 0;  // steadiness
  // Hops that start in the window: height (max centre height above the bed) and length (cm).
  MeanInterval hop_height, hop_length;
  std::vector<Crossing> impacts, liftoffs;                                // in the window
  MeanInterval impact_speed, impact_angle, liftoff_speed, liftoff_angle;  // cm/s, deg
  // Hops higher than 5 d (saltation proper, not reptation): height, length, impact speed and angle.
  MeanInterval salton_hop_height, salton_hop_length, salton_impact_speed, salton_impact_angle;
  // The mean downwind velocity of the grains more than one diameter above the bed (their flux over their
  // mass, from the profiles): "the mean grain velocity" that Creyssels et al. 2009 and Duran et al. 2012
  // find independent of u* in saltation (cm/s).
  double transport_velocity = 0;
  // The Ch. IV steady-state model run with the splash this simulation measured (same u*, grains, air).
  struct SteadyModel {
    bool ran = false, converged = false;
    std::string failure;
    double mass_flux = 0, u_star_eff = 0, hop_height = 0, hop_length = 0;
  } model;
  // Momentum: what the wind lost (its own tally) and what the grains got (sampled drag), per bed area,
  // averaged over the window (dyn/cm^2); and the stress partition at the bed tau_f + tau_g vs rho u*^2.
  double wind_momentum_loss = 0, grain_momentum_gain = 0, stress_partition = 0;
  // The coupling's lag: |grains' view - wind's view| per interval, averaged (dyn/cm^2).
  double coupling_lag = 0;
  // Profiles over z above the bed (cm): mass concentration (g/cm^3), mass flux density (g/(cm^2 s)),
  // wind with and without grains (cm/s), grain-borne stress (dyn/cm^2).
  std::vector<double> z, concentration, flux_density, wind, wind_clean, grain_stress;
  // Time series, one row per 10 samples: t, Q, u*_eff, airborne.
  std::vector<std::array<double, 4>> series;
  saltation::SplashFile splash;  // impacts by speed at the median angle (grainlab-splash/1)
  std::size_t grains = 0;
  double bed_width = 0, slab_thickness = 0, dt = 0;
  double wall_seconds = 0, wind_seconds = 0;  // wind_seconds: drag and updates (measured share)
  std::uint64_t steps = 0;
  bool stopped = false;  // ended at stop_at: only the checkpoint was written, nothing is measured
};

DemSaltationResult run_dem_saltation(const DemSaltationOptions& o);

}  // namespace grainlab::validation
