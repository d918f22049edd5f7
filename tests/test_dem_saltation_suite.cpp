// The dem-saltation suite's quick version: what grainlab claims for the wind coupling must pass: the
// wind loses what the grains gain by drag (to 1 %), and the stress partition closes (fluid plus
// grain-borne stress is rho u*^2). The flux exponent, impact-speed ratio and stiffness independence are
// reported and may fail at this size: docs/saltation.md gives the measured numbers.
#include <gtest/gtest.h>

#include "suites.hpp"

namespace grainlab::validation {

TEST(DemSaltationSuite, QuickClaimsHold) {
  Report r;
  SuiteOptions o;
  o.quick = true;
  run_dem_saltation_suite(r, o);
  int claimed = 0;
  for (const Check& c : r.checks) {
    const bool claim = c.id.find("/stress-partition") != std::string::npos ||
                       c.id.find("/momentum-balance") != std::string::npos;
    if (!claim) continue;
    ++claimed;
    EXPECT_TRUE(c.passed) << c.id << ": " << c.value << " against " << c.reference << " (" << c.note << ")";
  }
  EXPECT_EQ(claimed, 8);  // both balances for two u* and two stiffnesses
}

}  // namespace grainlab::validation
