// The accuracy-cost study: its bookkeeping, and that the engines' finest settings reach the analytic
// answers they should.
#include <gtest/gtest.h>

#include "accuracy_cost.hpp"

using namespace grainlab::validation;

namespace {
CostRow row(double dt, double error, double seconds) {
  return {.scene = "s",
          .engine = "native",
          .method = "m",
          .knob = "dt",
          .value = dt,
          .error = error,
          .seconds = seconds};
}
}  // namespace

TEST(AccuracyCost, CheapestReachingPicksTheFastestSettingUnderTheTarget) {
  std::vector<CostRow> rows = {row(1e-3, 0.05, 1.0), row(1e-4, 0.005, 2.0), row(1e-5, 0.004, 9.0)};
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-1), &rows[0]);
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-2), &rows[1]);
  EXPECT_EQ(cheapest_reaching(rows, "s", "m", 1e-3), nullptr);  // "not reached"
  EXPECT_EQ(cheapest_reaching(rows, "other", "m", 1e-1), nullptr);
}

TEST(AccuracyCost, FinestSettingsReachTheAnalyticAnswers) {
  // Rolling disc and sliding block: every engine's finest dt (quick mode: 2e-4 s for the impulse
  // engines, first order, so g dt-sized errors of up to 2e-3 relative) is within 2e-3 of the analytic
  // distance, and refining dt 25-fold from the coarsest setting cuts the error at least 5-fold unless it
  // is already at round-off and contact-model level (1e-5).
  for (const CostScene& sc : cost_scenes(true)) {
    if (sc.name != "rolling-disc" && sc.name != "slide-to-rest") continue;
    const double exact = sc.reference().value;
    for (const std::string engine : {"native", "box2d", "bullet", "ode"}) {
      const CostSetting *finest = nullptr, *coarsest = nullptr;
      for (const CostSetting& c : sc.settings) {
        if (c.engine != engine || c.knob != "dt" || c.method == "ode step") continue;
        if (!finest || c.value < finest->value) finest = &c;
        if (!coarsest || c.value > coarsest->value) coarsest = &c;
      }
      ASSERT_NE(finest, nullptr) << sc.name << " " << engine;
      const double fine = std::abs(sc.measure(*finest).value / exact - 1),
                   coarse = std::abs(sc.measure(*coarsest).value / exact - 1);
      EXPECT_LE(fine, 2e-3) << sc.name << " on " << engine;
      EXPECT_TRUE(fine < 1e-5 || fine * 5 <= coarse)
          << sc.name << " on " << engine << ": " << coarse << " at dt " << coarsest->value << ", " << fine
          << " at dt " << finest->value;
    }
  }
}
