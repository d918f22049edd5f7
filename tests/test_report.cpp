// The report part that `validate --jobs` children hand to their parent: everything survives the trip,
// numbers bit for bit (NaN and infinities too), and a damaged part is refused with a message.
#include <gtest/gtest.h>

#include <cmath>

#include "report.hpp"

using namespace grainlab::validation;

namespace {

Report sample_report() {
  Report r;
  r.expect_near("suite/a", "native", 0.1 + 0.2, 0.3, 1e-12, "exact decimal trouble");
  r.expect_near("suite/b", "ode", NAN, 1.0, INFINITY, "not measured").known_limitation("ODE cannot");
  r.expect_below("suite/c", "bullet", -INFINITY, 2.0, "below");
  r.markdown = {"# one\n\n| a | b |\n", "two \"quoted\" \\ text"};
  r.plots.push_back(
      {"p.png", "title", "x", "y", true, {{"s", "points", {1, 2}, {3, NAN}, {0.5, 0.25}}}, true});
  r.samples.push_back({"t/native", "rows", {"a", "b"}, {{1.0 / 3, 2e-300}, {-0.0, 7}}});
  r.times.push_back({"suite", 12.5});
  return r;
}

bool same_bits(double a, double b) {
  return std::isnan(a) ? std::isnan(b) : std::signbit(a) == std::signbit(b) && a == b;
}

}  // namespace

TEST(ReportPart, RoundTripKeepsEveryFieldBitForBit) {
  const Report a = sample_report();
  const Report b = read_report_part(report_part_json(a));
  ASSERT_EQ(b.checks.size(), a.checks.size());
  for (std::size_t k = 0; k < a.checks.size(); ++k) {
    EXPECT_EQ(b.checks[k].id, a.checks[k].id);
    EXPECT_EQ(b.checks[k].engine, a.checks[k].engine);
    EXPECT_EQ(b.checks[k].passed, a.checks[k].passed);
    EXPECT_EQ(b.checks[k].note, a.checks[k].note);
    EXPECT_EQ(b.checks[k].limitation, a.checks[k].limitation);
    EXPECT_TRUE(same_bits(b.checks[k].value, a.checks[k].value)) << k;
    EXPECT_TRUE(same_bits(b.checks[k].reference, a.checks[k].reference)) << k;
    EXPECT_TRUE(same_bits(b.checks[k].tolerance, a.checks[k].tolerance)) << k;
  }
  EXPECT_EQ(b.markdown, a.markdown);
  ASSERT_EQ(b.plots.size(), 1u);
  EXPECT_TRUE(b.plots[0].logx && b.plots[0].logy);
  EXPECT_EQ(b.plots[0].series[0].x, a.plots[0].series[0].x);
  EXPECT_TRUE(std::isnan(b.plots[0].series[0].y[1]));
  EXPECT_EQ(b.plots[0].series[0].err, a.plots[0].series[0].err);
  ASSERT_EQ(b.samples.size(), 1u);
  EXPECT_EQ(b.samples[0].columns, a.samples[0].columns);
  EXPECT_TRUE(same_bits(b.samples[0].rows[0][0], 1.0 / 3));
  EXPECT_TRUE(same_bits(b.samples[0].rows[0][1], 2e-300));
  EXPECT_TRUE(same_bits(b.samples[0].rows[1][0], -0.0));
  ASSERT_EQ(b.times.size(), 1u);
  EXPECT_EQ(b.times[0].seconds, 12.5);
  EXPECT_EQ(b.passed(), a.passed());
}

TEST(ReportPart, AppendKeepsOrder) {
  Report a = sample_report(), b = sample_report();
  b.checks[0].id = "other/a";
  a.append(std::move(b));
  ASSERT_EQ(a.checks.size(), 6u);
  EXPECT_EQ(a.checks[3].id, "other/a");
  EXPECT_EQ(a.times.size(), 2u);
}

TEST(ReportPart, DamagedPartsAreRefused) {
  const std::string good = report_part_json(sample_report());
  EXPECT_THROW(read_report_part(""), std::runtime_error);
  EXPECT_THROW(read_report_part(good.substr(0, good.size() / 2)), std::runtime_error);
  EXPECT_THROW(read_report_part("{\"schema\": \"something-else\"}"), std::runtime_error);
  EXPECT_THROW(read_report_part("{\"schema\": \"grainlab-report-part/1\", \"checks\": [{\"id\": 3}]}"),
               std::runtime_error);
  EXPECT_THROW(
      read_report_part(
          "{\"schema\": \"grainlab-report-part/1\", \"plots\": [{\"file\": \"a\", \"title\": \"\", "
          "\"xlabel\": \"\", \"ylabel\": \"\", \"logx\": false, \"logy\": false, \"series\": [{\"label\": "
          "\"\", \"style\": \"\", \"x\": [\"many\"], \"y\": [], \"err\": []}]}]}"),
      std::runtime_error);
}

#include "../cli/progress.hpp"

namespace grainlab::cli {

// The estimate of time left counts only what this clock saw done: a run continued at 12 % of its way,
// 60 s after restarting and now at 13 %, has 87 % left at 1 % a minute (87 min), not 60 s x 87 / 13.
TEST(ProgressBar, TimeLeftCountsOnlyTheWorkThisClockSaw) {
  EXPECT_NEAR(grainlab::time_left(60, 12, 13, 100), 87 * 60, 1e-9);
  EXPECT_NEAR(grainlab::time_left(60, 0, 25, 100), 180, 1e-9);  // a fresh run: as before
  EXPECT_EQ(grainlab::time_left(60, 12, 12, 100), 0);           // nothing done yet: no estimate
  EXPECT_EQ(grainlab::time_left(60, 0, 120, 100), 0);           // past the end
}

// On a shared machine a long run's pace changes: the estimate follows the last ten minutes. A run at
// 1 % a minute for 30 minutes, then at 0.1 % a minute for 20 (something else took the cores), has 68 %
// left: 680 minutes at its present pace, where its pace since the start (32 % in 50 min) would say 106.
TEST(ProgressBar, TimeLeftFollowsTheRecentPace) {
  grainlab::RecentPace pace;  // ten minutes, a sample at most every ten seconds
  double done = 0;
  for (int s = 0; s <= 3000; ++s) {
    pace.add(s, done);
    done += s < 1800 ? 1.0 / 60 : 0.1 / 60;
  }
  done -= 0.1 / 60;  // (the sample at 3000 s was the last)
  EXPECT_NEAR(pace.left(3000, done, 100), (100 - done) * 600, 1.0);
  EXPECT_NEAR(grainlab::time_left(3000, 0, done, 100), 6375, 1.0);  // the pace since the start
  // Younger than the window: the pace since the first sample, as before (a run continued at 12 %).
  grainlab::RecentPace resumed;
  resumed.add(0, 12), resumed.add(30, 12.5), resumed.add(60, 13);
  EXPECT_NEAR(resumed.left(60, 13, 100), 87 * 60, 1e-9);
  resumed.restart();
  EXPECT_EQ(resumed.left(60, 13, 100), 0);  // nothing since the restart: no estimate
}

}  // namespace grainlab::cli

#include "plot_script.hpp"

// A plot that fails says why: the script's own last line of error, not only its exit status (a run too
// short for ripples once failed its plot with nothing but "exited with status 1").
TEST(PlotScript, AFailedPlotSaysWhy) {
  using grainlab::validation::missing_for_plots;
  using grainlab::validation::run_plot_script;
  if (!missing_for_plots("plot_hybrid.py").empty()) GTEST_SKIP() << "no python3 here";
  const std::string why = run_plot_script("plot_hybrid.py", {"/nonexistent/run.h5"});
  EXPECT_NE(why.find("exited with status"), std::string::npos) << why;
  EXPECT_NE(why.find("/nonexistent/run.h5"), std::string::npos) << why;
}
