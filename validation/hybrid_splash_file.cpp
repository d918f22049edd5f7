#include "hybrid_splash_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "input_error.hpp"
#include "lammel_splash.hpp"

namespace grainlab::validation {

using ripples::hybrid::RecordedCell;
using ripples::hybrid::RecordedEjectum;
using ripples::hybrid::RecordedSplash;

namespace {
// The impact a row names, as an index into the cell's impacts.
std::size_t impact_of(double index, std::size_t impacts, const std::string& path) {
  if (!(index >= 0 && index < static_cast<double>(impacts)) || index != std::floor(index))
    throw InputError({path, 0}, "splash",
                     fmt::format("a row names impact {} of a cell of {}", index, impacts));
  return static_cast<std::size_t>(index);
}
}  // namespace

RecordedSplash recorded_splash(const saltation::SplashFile& f, const std::string& path) {
  RecordedSplash r;
  r.source = path, r.speeds = f.speeds, r.angles_deg = f.angles_deg;
  for (const saltation::SplashCell& c : f.cells) {
    RecordedCell& cell = r.cells.emplace_back();
    cell.speed = c.speed, cell.angle_deg = c.angle_deg;
    cell.impacts.resize(c.rebound.empty() ? 0 : c.impacts);
    for (std::size_t k = 0; k < c.rebound.size(); ++k) {
      const auto& row = c.rebound[k];
      auto& impact = cell.impacts[impact_of(row[0], cell.impacts.size(), path)];
      impact.rebounded = row[1] != 0;
      impact.rebound = {row[2], row[3], k < c.rebound_lateral.size() ? c.rebound_lateral[k] : 0.0};
    }
    for (std::size_t k = 0; k < c.ejecta.size() && !cell.impacts.empty(); ++k) {
      const auto& row = c.ejecta[k];
      RecordedEjectum e;
      const bool lateral = k < c.ejecta_lateral.size();
      e.launch = {row[3], row[4], lateral ? c.ejecta_lateral[k][0] : 0.0};
      e.along = row[5], e.across = lateral ? c.ejecta_lateral[k][1] : 0.0;
      cell.impacts[impact_of(row[0], cell.impacts.size(), path)].ejecta.push_back(e);
    }
  }
  try {
    r.check();
  } catch (const std::invalid_argument& e) {
    throw InputError({path, 0}, "splash", e.what());
  }
  return r;
}

RecordedSplash read_recorded_splash(const std::string& path) {
  return recorded_splash(saltation::read_splash_file(path), path);
}

void attach_recorded_splash(ripples::hybrid::TransportOptions& o) {
  if (ripples::hybrid::LammelParameters::is_named(o.splash)) return;
  o.recorded = std::make_shared<const RecordedSplash>(read_recorded_splash(o.splash));
}

}  // namespace grainlab::validation
