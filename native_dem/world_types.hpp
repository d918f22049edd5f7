#pragma once
// What the 2-D and 3-D native worlds report: energies and step diagnostics.
#include <cstddef>
#include <cstdint>

namespace grainlab::dem {

struct Energies {
  double kinetic_translational = 0, kinetic_rotational = 0, potential_gravity = 0, elastic = 0;
  double total() const { return kinetic_translational + kinetic_rotational + potential_gravity + elastic; }
  double kinetic() const { return kinetic_translational + kinetic_rotational; }
};

struct Diagnostics {
  std::uint64_t steps = 0, rejected_steps = 0, force_evaluations = 0, neighbor_rebuilds = 0;
  std::size_t contacts = 0, max_contacts = 0;
  double wall_seconds = 0;
  double dt_last = 0, dt_min_used = 0, dt_max_used = 0;
  // Where the time goes (wall seconds).
  double seconds_forces = 0, seconds_neighbors = 0;
  double seconds_wind = 0;  // wind_drag: the drag on every grain and the wind's tallies and updates
};

}  // namespace grainlab::dem
