// The ripples suite's quick version: the checks grainlab claims must pass (worms, triangular collisions,
// the continuum's growth rate, the bin model, the lattice model's brink / target contrast). The lattice
// runs' wavelengths, heights and slopes beside Figs 5.22-5.23 are compared in the report and may disagree:
// docs/ripples.md gives the measured values and what is known about why.
#include <gtest/gtest.h>

#include "suites.hpp"

namespace grainlab::validation {

TEST(RipplesSuite, QuickClaimsHold) {
  Report r;
  SuiteOptions o;
  o.quick = true;
  run_ripples_suite(r, o);
  int claimed = 0;
  for (const Check& c : r.checks) {
    const bool compared_only = c.id.find("/lattice/target-only-stoss") != std::string::npos ||
                               c.id.find("/lattice/target-only-lee") != std::string::npos ||
                               c.id.find("/lattice/fig5.2") != std::string::npos ||
                               c.id.find("/lattice/sand-gun-hops") != std::string::npos;
    if (compared_only) continue;
    ++claimed;
    EXPECT_TRUE(c.passed) << c.id << ": " << c.value << " against " << c.reference << " (" << c.note << ")";
  }
  // Worms 6, triangles 4 + 10 + the limiting wavelength, continuum 1, bins 2, lattice 2 + the linear
  // response's 4.
  EXPECT_EQ(claimed, 6 + 15 + 1 + 2 + 2 + 4);
}

}  // namespace grainlab::validation
