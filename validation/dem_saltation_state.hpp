#pragma once
// What `grainlab saltation dem` has measured so far (validation/dem_saltation.cpp): the state a checkpoint
// carries beside the world's, as tables for the checkpoint file and back.
#include <array>
#include <map>
#include <string>
#include <vector>

#include "dem_saltation.hpp"
#include "h5_output.hpp"
#include "world.hpp"

namespace grainlab::validation::dem_saltation_detail {

// What one grain is doing between samples: its unwrapped x, whether it is airborne, and its flight.
struct GrainTrack {
  double x = 0, y = 0, vx = 0, vy = 0, x_unwrapped = 0;
  bool airborne = false;
  Crossing up{};
  double peak = 0;
};

struct Flight {
  double t_up, height, length, impact_vx, impact_vy;
};

// One sample of the steady-state window: Q, u*_eff, airborne grains, the drag the grains got, what the
// wind lost, the stress partition and the coupling's lag.
using WindowSample = std::array<double, 7>;

struct StudyState {
  long next_sample = 0;  // index of the next sample to take (sample_interval apart, from t = 0)
  std::vector<GrainTrack> track;
  std::vector<Flight> flights;
  std::vector<Crossing> impacts, liftoffs;
  std::vector<std::array<double, 4>> series;  // t, Q, u*_eff, airborne: every 10th sample
  std::vector<WindowSample> window;
  // Sums over the window's samples per profile bin: mass, m v_x, wind, clean wind, grain stress.
  std::vector<double> mass_z, flux_z, wind_z, clean_z, tau_z;
};

// Writes the world's and the study's state to `path` (atomically), with the options they belong to.
void write_checkpoint(const std::string& path, const DemSaltationOptions& o, const dem::WorldState& world,
                      const StudyState& study);
// Reads a checkpoint written for the same options (InputError with key "--restart" otherwise, or for a
// damaged file).
std::pair<dem::WorldState, StudyState> read_checkpoint(const std::string& path, const DemSaltationOptions& o);

}  // namespace grainlab::validation::dem_saltation_detail
