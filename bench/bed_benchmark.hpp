#pragma once
// `grainlab bench bed`: the same work as bench/bed.in for LAMMPS (gran/hooke/history): a square
// lattice of discs dropped onto a frictional wall, periodic in x, fixed dt, timed after settling.
#include <cstdint>
#include <string>

#include "scene.hpp"

namespace grainlab::bench {

struct BedOptions {
  int nx = 100, ny = 50;
  int settle_steps = 2000, timed_steps = 10000, repeats = 3;
  double spacing = 2.02, first_row = 2.5;  // 2.0 and 1.0: discs start touching (dense variant)
  bool frictionless = false;
  std::uint64_t balance_every = 1000;  // distributed runs: re-split the regions every so many steps
  int ranks_y = 1;                     // distributed runs: rows of the grid of ranks
  std::string json;
};

struct BedResult {
  long particles = 0;
  int steps = 0;
  double median_seconds = 0, min_seconds = 0, max_seconds = 0;
  double particle_steps_per_second = 0;
  double bytes_per_particle = 0;
  double share_forces = 0, share_neighbors = 0;  // of the timed wall time
  double mean_height = 0, kinetic_energy = 0;    // state after settle + timed steps (physics cross-check)
  long contacts = 0, neighbor_rebuilds = 0;
  // Under mpirun (the distributed engine): ranks, the share of the step time spent exchanging ghosts,
  // migrating and agreeing (mean over ranks, waiting included), and the load imbalance: the slowest
  // rank's compute time over the mean.
  int ranks = 1;
  double share_communication = 0, imbalance = 1;
  long ghosts = 0;
};

// The bed as a scene (TOML text), so it runs through the same reader as any user scene.
std::string bed_scene_toml(const BedOptions& o);
BedResult run_bed(const BedOptions& o);
int run_bed_command(const BedOptions& o);

}  // namespace grainlab::bench
