// The accuracy-cost study: its bookkeeping, and that the engines' finest settings reach the analytic
// answers they should.
#include <gtest/gtest.h>

#include "accuracy_cost.hpp"

using namespace grainlab::validation;

TEST(AccuracyCost, CheapestReachingPicksTheFastestSettingUnderTheTarget) {
  std::vector<CostRow> rows(3);
  rows[0] = {"s", "native", "m", "dt", 1e-3, 0, 0.05, 0, 1.0, 0, 0, 0, ""};
  rows[1] = {"s", "native", "m", "dt", 1e-4, 0, 0.005, 0, 2.0, 0, 0, 0, ""};
  rows[2] = {"s", "native", "m", "dt", 1e-5, 0, 0.004, 0, 9.0, 0, 0, 0, ""};
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-1), &rows[0]);
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-2), &rows[1]);
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-3), nullptr);  // "not reached"
  EXPECT_EQ(cheapest_reaching(rows, "other", "m", 1e-1), nullptr);
}

TEST(AccuracyCost, FinestSettingsReachTheAnalyticAnswers) {
  // Rolling disc and sliding block: every engine's finest dt within 1e-3 of the analytic distance.
  for (const CostScene& sc : cost_scenes(true)) {
    if (sc.name != "rolling-disc" && sc.name != "slide-to-rest") continue;
    const double exact = sc.reference().value;
    for (const std::string engine : {"native", "box2d", "bullet", "ode"}) {
      const CostSetting* finest = nullptr;
      for (const CostSetting& c : sc.settings)
        if (c.engine == engine && c.knob == "dt" && (!finest || c.value < finest->value)) finest = &c;
      ASSERT_NE(finest, nullptr) << sc.name << " " << engine;
      EXPECT_NEAR(sc.measure(*finest).value / exact, 1.0, 2e-3) << sc.name << " on " << engine;
    }
  }
}
