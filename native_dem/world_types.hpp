#pragma once
// What the 2-D and 3-D native worlds report: energies and step diagnostics.
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>

namespace grainlab::dem {

struct Energies {
  double kinetic_translational = 0, kinetic_rotational = 0, potential_gravity = 0, elastic = 0;
  double total() const { return kinetic_translational + kinetic_rotational + potential_gravity + elastic; }
  double kinetic() const { return kinetic_translational + kinetic_rotational; }
};

// Per touching pair (body ids; a wall or plane k as -1 - k): the summed normal force at one evaluation, or
// the normal impulse over a step (what contact events are built from).
using PairForces = std::map<std::pair<std::int64_t, std::int64_t>, double>;

// The trapezoid rule over a step of length `taken`, the rule both integrators apply: each pair's impulse
// from its normal force at the step's start and at its end.
inline void trapezoid_impulses(const PairForces& at_start, const PairForces& at_end, double taken,
                               PairForces& impulses) {
  impulses.clear();
  for (const auto& [pair, fn] : at_start) impulses[pair] = fn * taken / 2;
  for (const auto& [pair, fn] : at_end) impulses[pair] += fn * taken / 2;
}

struct Diagnostics {
  std::uint64_t steps = 0, rejected_steps = 0, force_evaluations = 0, neighbor_rebuilds = 0;
  std::uint64_t region_recuts = 0;  // distributed sphere beds: re-cuts to the ranks' measured speeds
  std::size_t contacts = 0, max_contacts = 0;
  double wall_seconds = 0;
  double dt_last = 0, dt_min_used = 0, dt_max_used = 0;
  // Where the time goes (wall seconds).
  double seconds_forces = 0, seconds_neighbors = 0;
  double seconds_wind = 0;  // wind_drag: the drag on every grain and the wind's tallies and updates
};

}  // namespace grainlab::dem
