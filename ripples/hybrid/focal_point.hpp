#pragma once
// The wind over saltation and its focal point (Huo et al. 2021, section 3.4, Fig. 14 and eq. 32; Bagnold's
// "focus"). Above the saltation layer the wind is a log layer, u = (u*/kappa) ln(z / z0), whose roughness
// z0 the grains set. Within it the grains slow the wind the more the stronger it blows, so profiles at
// different u* meet near one height z_F, at one speed u_F. If they all pass through (z_F, u_F), the log
// layer gives z0 = z_F exp(-kappa u_F / u*): ln z0 is linear in 1 / u*. Both ways of finding the point
// are here: where the profiles cross, and the line through ln z0 against 1 / u*.
#include <cstddef>
#include <optional>
#include <vector>

#include "wind_column.hpp"

namespace grainlab::ripples::hybrid {

struct WindProfile {
  double u_star = 0;         // cm/s
  std::vector<double> z, u;  // heights (cm, increasing) and the wind there (cm/s)
};

// z0 of the log layer over heights in [z_lo, z_hi]: the mean over the profile's nodes there of
// ln z - kappa u / u*, which is ln z0 at every node of an exact log layer. `spread` is that quantity's
// range over the band (0 for an exact log layer). Throws std::invalid_argument if no node lies in the band.
struct LogLayerFit {
  double z0 = 0, spread = 0;
  std::size_t nodes = 0;
};
LogLayerFit log_layer_roughness(const WindProfile& p, double z_lo, double z_hi,
                                double kappa = WindColumn::kKappa);

// Where two profiles on the same heights cross: the lowest height above z_min at which u_a - u_b changes
// sign, the winds interpolated linearly in ln z between the nodes (the columns' meshes are geometric). None
// if they do not cross there.
struct ProfileCrossing {
  double u_star_a = 0, u_star_b = 0, z = 0, u = 0;
};
std::optional<ProfileCrossing> profile_crossing(const WindProfile& a, const WindProfile& b, double z_min);

struct FocalPoint {
  std::vector<LogLayerFit> log_layers;  // one per profile, in the order given
  // ln z0 = ln z_F - kappa u_F / u*, by least squares in 1 / u*; r2 is the line's coefficient of
  // determination.
  double fit_z = 0, fit_u = 0, fit_r2 = 0;
  // Every pair's crossing, and their medians and range of heights.
  std::vector<ProfileCrossing> crossings;
  std::size_t pairs = 0;  // pairs tried (crossings.size() of them crossed)
  double crossing_z = 0, crossing_u = 0, crossing_z_min = 0, crossing_z_max = 0;
};
// The crossings are sought on heights every profile covers (each resampled linearly in ln z: the columns'
// meshes differ with u*). Needs at least two profiles with distinct u*; throws std::invalid_argument
// otherwise.
FocalPoint focal_point(const std::vector<WindProfile>& profiles, double z_lo, double z_hi, double z_min,
                       double kappa = WindColumn::kKappa);

}  // namespace grainlab::ripples::hybrid
