#include "convergence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstddef>

namespace grainlab::saltation {

bool FluxWatch::dying(double total) {
  peak_ = std::max(peak_, total);
  return total < 1e-9 * peak_;
}

// A stall is an oscillation the damping does not remove.
std::string why_not_converged(const std::vector<double>& residuals, double tolerance) {
  const std::size_t n = residuals.size(), window = std::max<std::size_t>(50, n / 4);
  if (n == 0) return "no iterations";
  if (n >= 2 * window) {
    const auto [lo, hi] =
        std::minmax_element(residuals.end() - static_cast<std::ptrdiff_t>(window), residuals.end());
    const double before =
        *std::min_element(residuals.begin(), residuals.end() - static_cast<std::ptrdiff_t>(window));
    if (*lo >= 0.5 * before)
      return fmt::format(
          "stalled: the largest change stayed between {:.3g} and {:.3g} over the last {} iterations "
          "(tolerance {:.3g}) without falling: the iteration oscillates about a state it does not reach",
          *lo, *hi, window, tolerance);
  }
  return fmt::format("not converged in {} iterations (last change {:.3g}, tolerance {:.3g})", n,
                     residuals.back(), tolerance);
}

}  // namespace grainlab::saltation
