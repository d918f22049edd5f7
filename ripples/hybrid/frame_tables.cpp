#include "frame_tables.hpp"

#include <cmath>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

namespace {

// Histories written before frames carried the log layer's roughness (2026-11-28) lack its column, the
// flank slopes' (2026-12-03), the collision rate's and the crest measures' (2026-12-04); those written
// between, the later ones. Their frames read NaN there.
constexpr std::size_t kColumnsBeforeZ0 = 12, kColumnsBeforeSlopes = 13, kColumnsBeforeCollisions = 15,
                      kColumnsBeforeCrests = 16;

bool known_columns(const std::vector<std::string>& columns) {
  const std::vector<std::string>& all = frame_history_columns();
  if (columns == all) return true;
  for (std::size_t n :
       {kColumnsBeforeZ0, kColumnsBeforeSlopes, kColumnsBeforeCollisions, kColumnsBeforeCrests})
    if (columns == std::vector<std::string>(all.begin(), all.begin() + static_cast<long>(n))) return true;
  return false;
}

BedFrame frame_of_row(const std::vector<double>& r) {
  BedFrame f;
  f.t_star = r[0], f.stats = {r[1], r[2], r[3], r[4]}, f.shift = r[5], f.mass_flux_star = r[6];
  f.airborne = r[7], f.u_star_bed = r[8], f.loosening = r[9], f.size_crest = r[10], f.size_trough = r[11];
  if (r.size() > kColumnsBeforeZ0) f.z0 = r[12];
  f.stats.stoss_deg = f.stats.lee_deg = std::nan("");
  if (r.size() > kColumnsBeforeSlopes) f.stats.stoss_deg = r[13], f.stats.lee_deg = r[14];
  if (r.size() > kColumnsBeforeCollisions) f.collision_rate = r[15];
  f.stats.crest_spacing = f.stats.crest_height = f.stats.crest_ripple_index = std::nan("");
  if (r.size() > kColumnsBeforeCrests)
    f.stats.crest_spacing = r[16], f.stats.crest_height = r[17], f.stats.crest_ripple_index = r[18];
  return f;
}

}  // namespace

const std::vector<std::string>& frame_history_columns() {
  static const std::vector<std::string> columns = {
      "t_star",         "amplitude",      "wavelength",   "ripple_index",      "mean_height",
      "shift",          "mass_flux_star", "airborne",     "u_star_bed",        "loosening",
      "size_crest",     "size_trough",    "z0",           "stoss_deg",         "lee_deg",
      "collision_rate", "crest_spacing",  "crest_height", "crest_ripple_index"};
  return columns;
}

std::vector<double> frame_history_row(const BedFrame& f) {
  return {f.t_star,
          f.stats.amplitude,
          f.stats.wavelength,
          f.stats.ripple_index,
          f.stats.mean,
          f.shift,
          f.mass_flux_star,
          f.airborne,
          f.u_star_bed,
          f.loosening,
          f.size_crest,
          f.size_trough,
          f.z0,
          f.stats.stoss_deg,
          f.stats.lee_deg,
          f.collision_rate,
          f.stats.crest_spacing,
          f.stats.crest_height,
          f.stats.crest_ripple_index};
}

std::vector<SampleTable> frame_tables(const std::vector<BedFrame>& frames, std::size_t nx, bool sizes,
                                      const std::string& prefix) {
  SampleTable history{prefix + "history", "frames so far", frame_history_columns(), {}};
  std::vector<double> profiles, size_profiles;
  for (const BedFrame& f : frames) {
    history.rows.push_back(frame_history_row(f));
    profiles.insert(profiles.end(), f.profile.begin(), f.profile.end());
    size_profiles.insert(size_profiles.end(), f.size_profile.begin(), f.size_profile.end());
  }
  std::vector<SampleTable> out{history,
                               grid_table(prefix + "profiles", "each frame's profile (d)", profiles, nx)};
  if (sizes)
    out.push_back(
        grid_table(prefix + "size_profiles", "each frame's mean surface size (d)", size_profiles, nx));
  return out;
}

std::map<std::string, std::vector<std::string>> frame_table_names(bool sizes, const std::string& prefix) {
  std::map<std::string, std::vector<std::string>> names{{prefix + "history", {}}, {prefix + "profiles", {}}};
  if (sizes) names[prefix + "size_profiles"] = {};
  return names;
}

std::vector<BedFrame> frames_of_tables(const std::map<std::string, SampleTable>& tables, std::size_t nx,
                                       double dx, bool sizes, const std::string& prefix) {
  const SampleTable& history = checkpoint_table(tables, prefix + "history");  // (known_columns judges it)
  if (!known_columns(history.columns))
    throw std::invalid_argument("has a frame history with other columns than a hybrid ripple run writes");
  const auto& profiles = checkpoint_table(tables, prefix + "profiles", nx).rows;
  if (history.rows.empty() || profiles.size() != history.rows.size())
    throw std::invalid_argument("has no frames, or profiles missing");
  std::vector<BedFrame> frames;
  for (std::size_t k = 0; k < history.rows.size(); ++k) {
    frames.push_back(frame_of_row(history.rows[k]));
    frames.back().profile = profiles[k], frames.back().dx = dx;
  }
  if (sizes) {
    const auto& rows = checkpoint_table(tables, prefix + "size_profiles", nx).rows;
    if (rows.size() != frames.size())
      throw std::invalid_argument("has surface sizes for another number of frames");
    for (std::size_t k = 0; k < rows.size(); ++k) frames[k].size_profile = rows[k];
  }
  return frames;
}

}  // namespace grainlab::ripples::hybrid
