#include "clean_wind_heights.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace grainlab::saltation {

namespace {
void check(const CleanWindSpec& s) {
  auto positive = [](double v, const std::string& what) {
    if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(what + " must be positive");
  };
  positive(s.u_star, "u*"), positive(s.roughness, "the roughness length"), positive(s.g, "g");
  positive(s.grain_density, "the grain density");
  if (!(s.top > s.roughness))
    throw std::invalid_argument("the wind table's top must lie above the roughness");
  for (double d : s.diameters) positive(d, "a grain diameter");
  for (double v : s.speeds) positive(v, "a launch speed");
  for (double a : s.angles)
    if (!(a >= 0 && a < 90))
      throw std::invalid_argument("a launch angle must lie in [0, 90) deg from the vertical");
}
}  // namespace

std::vector<CleanWindLaunch> clean_wind_heights(const CleanWindSpec& s) {
  check(s);
  WindModelOptions o;
  o.fluid = s.fluid, o.g = s.g, o.u_star = s.u_star, o.top = s.top;
  o.grain.density = s.grain_density;
  // Eq. 4.28 on a table from the roughness length up (wind_at takes still air below its first height).
  std::vector<double> y(o.heights), u(o.heights);
  for (int k = 0; k < o.heights; ++k) {
    y[k] = s.roughness * std::pow(s.top / s.roughness, static_cast<double>(k) / (o.heights - 1));
    u[k] = s.fluid.k * s.u_star * std::log(y[k] / s.roughness);
  }
  std::vector<CleanWindLaunch> out;
  for (double d : s.diameters) {
    o.grain.radius = d / 2;
    for (double angle : s.angles)
      for (double v_oy : s.speeds) {
        const Trajectory t = fly(o, y, u, v_oy * std::tan(angle * M_PI / 180), v_oy);
        out.push_back({d, angle, v_oy, t.height, t.length, t.time, t.v_ix, t.v_iy, v_oy * v_oy / (2 * s.g)});
      }
  }
  return out;
}

double height_exponent_at_top(const std::vector<CleanWindLaunch>& launches, double diameter, double angle) {
  const CleanWindLaunch *top = nullptr, *next = nullptr;
  for (const CleanWindLaunch& l : launches) {
    if (l.diameter != diameter || l.angle != angle) continue;
    if (!top || l.v_oy > top->v_oy)
      next = top, top = &l;
    else if (!next || l.v_oy > next->v_oy)
      next = &l;
  }
  if (!top || !next || !(top->v_oy > next->v_oy) || !(next->height > 0))
    return std::numeric_limits<double>::quiet_NaN();
  return std::log(top->height / next->height) / std::log(top->v_oy / next->v_oy);
}

}  // namespace grainlab::saltation
