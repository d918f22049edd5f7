#include "recorded_splash.hpp"

#include <algorithm>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

namespace {
// Index of the value of an ascending axis nearest x.
std::size_t nearest_on(const std::vector<double>& axis, double x) {
  const auto above = std::lower_bound(axis.begin(), axis.end(), x);
  if (above == axis.begin()) return 0;
  if (above == axis.end()) return axis.size() - 1;
  const auto below = above - 1;
  return static_cast<std::size_t>((x - *below <= *above - x ? below : above) - axis.begin());
}
}  // namespace

void RecordedSplash::check() const {
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("recorded splash " + source + ": " + why);
  };
  for (const RecordedCell& c : cells)
    if (c.impacts.empty()) fail("a cell holds no recorded impacts (a measured file with moments only?)");
  if (speeds.empty() || angles_deg.empty()) fail("has no grid");
  if (!std::is_sorted(speeds.begin(), speeds.end()) || !std::is_sorted(angles_deg.begin(), angles_deg.end()))
    fail("grid is not ascending");
  if (cells.size() != speeds.size() * angles_deg.size()) fail("cells do not fill the grid");
}

const RecordedCell& RecordedSplash::nearest(double speed, double angle_deg) const {
  return cells[nearest_on(speeds, speed) * angles_deg.size() + nearest_on(angles_deg, angle_deg)];
}

const RecordedImpact& RecordedCell::draw(double u) const {
  const auto k =
      std::min(impacts.size() - 1, static_cast<std::size_t>(u * static_cast<double>(impacts.size())));
  return impacts[k];
}

}  // namespace grainlab::ripples::hybrid
