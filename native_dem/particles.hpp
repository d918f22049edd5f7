#pragma once
// Particle state as structure-of-arrays: the hot loops stream through plain double arrays.
#include <cstdint>
#include <vector>

namespace grainlab::dem {

struct Particles {
  // State.
  std::vector<double> x, y, th, vx, vy, w;
  // Velocities at the start of the previous step (the predictor-corrector's v_c(t0 - dt_-1)).
  std::vector<double> vx_prev, vy_prev, w_prev;
  // Accumulated force and torque.
  std::vector<double> fx, fy, tq;
  // Properties.
  std::vector<double> m, inv_m, inertia, inv_inertia, r;  // r: disc radius or polygon bounding radius
  std::vector<std::int64_t> id;     // stable id: keys contact history, survives reordering
  std::vector<std::int32_t> shape;  // -1: disc; otherwise index into the polygon shapes
  std::vector<std::int32_t> mat;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
  // Reorders every array so that new[k] = old[order[k]] (spatial sorting for cache locality); an order
  // shorter than size() keeps only the particles it lists.
  void permute(const std::vector<std::uint32_t>& order);
  static constexpr std::size_t bytes_per_particle() { return 21 * sizeof(double) + 8 + 4 + 4; }
};

}  // namespace grainlab::dem
