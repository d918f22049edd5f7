#pragma once
// The hybrid model's wind: steady and horizontally homogeneous (Huo et al. 2021, eqs 20-27), a van Driest
// mixing length (kappa 0.42) over a smooth wall, and the stress the grains' drag takes up subtracted from
// u*^2 from the top down. Solved on a mesh geometric from the wall (its first node in the viscous
// sublayer) and looked up by the grains in a table uniform in height, so the hot loop takes no logarithm.
// Heights are above the bed's mean level; the grains' drag and volume are tallied in the table's bins.
#include <cmath>
#include <cstddef>
#include <vector>

#include "fluid.hpp"

namespace grainlab::ripples::hybrid {

struct WindColumnParams {
  double u_star = 40, viscosity = 0.146, fluid_density = 0.00123, diameter = 0.025;  // cm, s, g
  double top = 30;                                                                   // cm
};

// The wind table as the grains read it, by value: a hot loop that holds a copy keeps these numbers in
// registers, where the column's own members might be changed (as far as the compiler knows) by every
// store the loop makes to a double.
struct WindTable {
  static constexpr double kKappa = 0.42;
  const double* u;
  double inv_h, u_star, top;
  std::size_t bins;
  // The table's bin at height z (the top bin takes everything above).
  std::size_t bin(double z) const {
    const double s = std::max(z, 0.0) * inv_h;
    return s < static_cast<double>(bins - 1) ? static_cast<std::size_t>(s) : bins - 1;
  }
  double at(double z) const {
    const double s = std::max(z, 0.0) * inv_h;
    if (s >= static_cast<double>(bins - 1)) return u[bins - 1] + u_star / kKappa * std::log(z / top);
    const auto k = static_cast<std::size_t>(s);
    const double a = s - static_cast<double>(k);
    return u[k] + a * (u[k + 1] - u[k]);
  }
};

class WindColumn {
 public:
  static constexpr double kKappa = WindTable::kKappa;
  explicit WindColumn(const WindColumnParams& p);
  std::size_t bins() const { return bins_; }
  WindTable table() const { return {table_.data(), inv_h_, p_.u_star, p_.top, bins_}; }  // valid until solve
  std::size_t bin(double z) const { return table().bin(z); }
  double at(double z) const { return table().at(z); }
  // Solves the steady column for the grains' drag (dyn) and solid volume (cm^3) per table bin over the bed
  // area: each node's stress is u*^2 less the drag above it, over 1 - phi.
  void solve(const std::vector<double>& drag, const std::vector<double>& volume, double area);
  const std::vector<double>& z() const { return z_; }
  const std::vector<double>& u() const { return u_; }
  const std::vector<double>& clean() const { return clean_; }
  double bed_stress() const { return bed_stress_; }  // tau_f / rho_f at the wall, cm^2/s^2

 private:
  static constexpr double kBinHeight = 0.1;  // diameters
  double mesh_at(double z, std::size_t node) const;
  WindColumnParams p_;
  fluid::WindProfileInput in_;
  double h_ = 1, inv_h_ = 1, bed_stress_ = 0;
  std::size_t bins_ = 0;
  std::vector<double> z_, u_, clean_, table_;
  std::vector<std::size_t> bin_cell_, bin_node_;  // per table bin: its mesh cell (drag), its node below
};

}  // namespace grainlab::ripples::hybrid
