#include "die_model.hpp"

#include <algorithm>
#include <cmath>

namespace grainlab::validation {

DieModel die_model(double f, double eps, DieModelVariant variant) {
  DieModel d;
  const double r2 = std::sqrt(2.0);
  d.high_well = variant == DieModelVariant::Printed ? f : 2 * f;
  const double w = d.high_well;
  d.e_low = (r2 - 1) * (1 - f);
  d.e_mid = r2 * std::sqrt(1 + f * f) - (1 - f);
  d.e_high = (r2 - 1) * (1 + f) + w;  // the barrier (r2 - 1)(1 + f) a above the high well
  // Energy after one and two collisions is e2 and e4 times the energy before. Near eps = 0 every window
  // scales as 1/eps^2, so the windows are computed times eps^2 (p_h is a ratio) to keep the limit finite.
  const double e2 = eps * eps;
  const double El = d.e_low, EM = d.e_mid, Eh = d.e_high;
  d.window[0] = std::max(0.0, El - EM * e2);
  d.window[1] = std::max(0.0, std::min(EM, El / e2) - El * e2);
  d.window[2] = std::max(0.0, std::min(Eh - w + w * e2, (EM - w) / e2 + w * e2) - EM * e2);
  d.window[3] = std::max(0.0, EM - w + w * e2 - Eh * e2);
  const double low_down = d.window[0] + d.window[1], total = low_down + d.window[2] + d.window[3];
  d.p_h = total > 0 ? low_down / total : 0.5;
  for (double& x : d.window) x = e2 > 0 ? x / e2 : HUGE_VAL;  // back to energy units
  return d;
}

}  // namespace grainlab::validation
