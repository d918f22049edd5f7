// The dem-saltation suite's quick version: what grainlab claims for the wind coupling must pass (the
// momentum the wind loses is what the grains receive, the stress partition closes). The flux exponent,
// impact-speed ratio and stiffness independence are compared with the literature in the report and are
// allowed to disagree here: docs/saltation.md gives the measured numbers.
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
    const bool claim = c.id.find("/momentum-balance") != std::string::npos ||
                       c.id.find("/stress-partition") != std::string::npos;
    if (!claim) continue;
    ++claimed;
    EXPECT_TRUE(c.passed) << c.id << ": " << c.value << " against " << c.reference << " (" << c.note << ")";
  }
  EXPECT_EQ(claimed, 2 * 4);  // two u* and two stiffnesses, two claims each
}

}  // namespace grainlab::validation
