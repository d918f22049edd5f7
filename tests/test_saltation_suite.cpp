// The saltation suite's quick version: what grainlab claims for the Ch. IV models must pass (the
// conveyor-belt steady states, the wind-driven model's convergence and exact identities, u*_eff falling
// with u*). Table 4.4 / 4.5, the text means and the flux exponent are compared in the report and are
// allowed to disagree here: docs/saltation.md gives the measured differences and what is known about them.
#include <gtest/gtest.h>

#include "suites.hpp"

namespace grainlab::validation {

TEST(SaltationSuite, QuickClaimsHold) {
  Report r;
  SuiteOptions o;
  o.quick = true;
  run_saltation_suite(r, o);
  int claimed = 0;
  for (const Check& c : r.checks) {
    const bool claim =
        c.id.find("/conveyor/") != std::string::npos || c.id.find("/identity-") != std::string::npos ||
        c.id.find("/converged") != std::string::npos || c.id.find("/decreasing") != std::string::npos ||
        c.id.find("/flux-square-law/") != std::string::npos;
    if (!claim) continue;
    ++claimed;
    EXPECT_TRUE(c.passed) << c.id << ": " << c.value << " against " << c.reference << " (" << c.note << ")";
  }
  // Conveyor: D in two orders (6), the closed form (2), Table 4.1 A and C (2); per wind cell (6):
  // converged and two identities; the two cases' orderings and flux laws (Q linear in u*^2).
  EXPECT_EQ(claimed, 10 + 6 * 3 + 2 + 2);
}

}  // namespace grainlab::validation
