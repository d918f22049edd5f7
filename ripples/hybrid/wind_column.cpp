#include "wind_column.hpp"

#include <algorithm>

namespace grainlab::ripples::hybrid {

namespace {
constexpr std::size_t kWindNodes = 240;
}

WindColumn::WindColumn(const WindColumnParams& p) : p_(p) {
  const double first = std::min(0.05 * p.viscosity / p.u_star, 0.01 * p.diameter);
  const double ratio = std::pow(p.top / first, 1.0 / static_cast<double>(kWindNodes - 1));
  for (std::size_t k = 0; k < kWindNodes; ++k) z_.push_back(first * std::pow(ratio, static_cast<double>(k)));
  in_ = {WindSpec::Model::VanDriest, kKappa, 0.0, p.viscosity, p.u_star};  // smooth wall, u(0) = 0
  h_ = kBinHeight * p.diameter;
  bins_ = static_cast<std::size_t>(std::ceil(p.top / h_)) + 1;
  inv_h_ = 1 / h_;
  // Where each table bin falls on the mesh never changes: found once here, not at every wind update (the
  // two searches per bin were a tenth of a small flux run's time).
  for (std::size_t b = 0; b < bins_; ++b) {
    const double zc = (static_cast<double>(b) + 0.5) * h_;
    const auto k = static_cast<std::size_t>(std::lower_bound(z_.begin(), z_.end(), zc) - z_.begin());
    bin_cell_.push_back(std::clamp<std::size_t>(k, 1, kWindNodes - 1) - 1);  // between nodes cell, cell+1
    const double z = static_cast<double>(b) * h_;
    bin_node_.push_back(
        z <= z_[0] || z >= z_.back()
            ? 0
            : static_cast<std::size_t>(std::upper_bound(z_.begin(), z_.end(), z) - z_.begin()) - 1);
  }
  const std::vector<double> none(bins_, 0.0);
  solve(none, none, 1);
  clean_ = u_;
}

void WindColumn::solve(const std::vector<double>& drag, const std::vector<double>& volume, double area) {
  std::vector<double> cell_drag(kWindNodes, 0.0), cell_volume(kWindNodes, 0.0);
  for (std::size_t b = 0; b < bins_; ++b)
    cell_drag[bin_cell_[b]] += drag[b], cell_volume[bin_cell_[b]] += volume[b];
  std::vector<double> stress(kWindNodes);
  double above = 0;  // tau_p / rho_f from the top down
  for (std::size_t k = kWindNodes; k-- > 0;) {
    stress[k] = p_.u_star * p_.u_star - above;
    if (k == 0) break;
    const double phi = std::min(0.9, cell_volume[k - 1] / (area * (z_[k] - z_[k - 1])));
    above += cell_drag[k - 1] / (1 - phi) / (area * p_.fluid_density);
  }
  u_ = fluid::wind_profile(in_, z_, stress);
  bed_stress_ = std::max(0.0, stress[0]);
  table_.resize(bins_);
  for (std::size_t b = 0; b < bins_; ++b) table_[b] = mesh_at(static_cast<double>(b) * h_, bin_node_[b]);
}

// The wind at height z, which lies between mesh nodes k and k + 1 (k is ignored below the first node and
// above the last).
double WindColumn::mesh_at(double z, std::size_t k) const {
  if (z <= z_[0]) return u_[0] * std::max(z, 0.0) / z_[0];
  if (z >= z_.back()) return u_.back();
  const double a = (z - z_[k]) / (z_[k + 1] - z_[k]);
  return u_[k] * (1 - a) + u_[k + 1] * a;
}

}  // namespace grainlab::ripples::hybrid
