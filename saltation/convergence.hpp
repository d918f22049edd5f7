#pragma once
// What the saltation solvers' fixed-point iterations share: telling a flux that dies (F = 0 is a fixed
// point of every one of them) from one that settles, and saying why an iteration stopped short.
#include <string>
#include <vector>

namespace grainlab::saltation {

// Watches the total flux, one value per iteration.
class FluxWatch {
 public:
  // True once the total is nine decades below its largest so far: heading for F = 0, not settling (the
  // relative change would otherwise stall at the decay factor, then read as converged once F underflows).
  bool dying(double total);

 private:
  double peak_ = 0;
};

// Why an iteration with these residuals (one per step) stopped short of `tolerance`: "stalled: ..." when
// the change has not fallen over the last quarter of the steps (at least 50), else the iteration limit.
std::string why_not_converged(const std::vector<double>& residuals, double tolerance);

}  // namespace grainlab::saltation
