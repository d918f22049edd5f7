#pragma once
// The thesis's proposed time-dependent saltation model (Ch. IV, eq. 4.35): the steady model of Fig. 4.10
// followed in time instead of iterated to its fixed point. Grains launched at time t fly through the wind
// of that moment and land a flight time later, where the splash function launches the next grains; the
// wind is taken, as the thesis proposes, to follow the drag of the grains in the air at each instant
// (its response time short beside a flight). There is no fluid entrainment: a seed of launches at t = 0
// starts the flux, which grows, saturates or dies. What it answers that the fixed point cannot: how long
// the system takes to reach its steady state, whether it gets there or oscillates, and how it answers a
// change of u* (a gust).
#include <map>
#include <string>
#include <vector>

#include "wind_model.hpp"

namespace grainlab::saltation {

struct TransientOptions {
  WindModelOptions model;  // grain, air, grids and the u* before the first change
  double dt = 0.005;       // s: flights are rounded to whole steps
  double duration = 4;     // s
  // Changes of u* at given times (a gust): (t, u*) pairs, in increasing t.
  std::vector<std::pair<double, double>> ustar_changes;
  int record_every = 1;  // steps between recorded samples
};

struct TransientSample {
  double t = 0, u_star = 0;
  double launch_rate = 0;  // grains per cm^2 per s leaving the bed in this step
  double airborne = 0;     // grains per cm^2 in the air
  double mass_flux = 0;    // g / (cm s): the grains in the air times their horizontal speed
  double u_star_eff = 0;   // sqrt(stress at the bed / rho)
};

struct TransientResult {
  std::vector<TransientSample> samples;
  bool died = false;  // the flux fell to nothing (under 1e-9 of the most grains it had in the air)
  std::string failure;
  // Time from the last change of u* (or from the seed) until the mass flux first came within 5 % of its
  // mean over the run's last fifth, and stayed there; -1 if it never settled.
  double settling_time = -1;
  double final_mass_flux = 0, final_u_star_eff = 0;  // means over the last fifth of the run
  // d ln(grains in the air) / dt over the last fifth (1/s): about 0 once settled, the growth or decay
  // rate of a flux still far from its steady state (below the threshold it is the rate of dying).
  double final_growth_rate = 0;
  double wall_seconds = 0;
};

// Throws std::invalid_argument on options it cannot run (dt, duration or u* not positive, changes out of
// order).
TransientResult run_transient(const TransientOptions& o, const SplashKernel& splash);

// The same run in pieces, so that it can be checkpointed: everything a run carries from one step to the
// next. A run continued from a saved state ends bit for bit as one never stopped.
struct TransientLanding {  // the grains landing at one step (see transient.cpp)
  std::vector<double> count, vx, vy, drag;
  double flux = 0, airborne = 0;
};
struct TransientState {
  long next_step = 0;           // the step to run next
  std::size_t next_change = 0;  // the first change of u* not yet made
  double u_star = 0, since = 0, most = 0, flux = 0, airborne = 0;
  std::vector<double> drag, born, vox;  // per height bin; per launch bin (the launches of next_step if 0)
  std::map<long, TransientLanding> landings;
  TransientResult result;  // the samples so far; died and failure once over
  bool over = false;
};
TransientState start_transient(const TransientOptions& o);
long transient_last_step(const TransientOptions& o);  // the run ends after this step
// Runs steps up to and including `stop_step` (or to the end); true once the run is over.
bool advance_transient(const TransientOptions& o, const SplashKernel& splash, TransientState& s,
                       long stop_step);
// The summary of a state that is over (or of the steps so far).
TransientResult finish_transient(const TransientState& s);

}  // namespace grainlab::saltation
