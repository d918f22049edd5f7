// The conveyor-belt model (thesis Ch. IV section 1) against its closed form and the spec's numbers.
#include <gtest/gtest.h>

#include <cmath>

#include "cli_helpers.hpp"
#include "conveyor.hpp"

using namespace grainlab::saltation;

TEST(ConveyorDelta, ClosedFormIdentities) {
  // Eqs 4.3-4.5 at Table 4.2 D's values: (F, v_oy, v_c) = (200, 1.25, 5), N = 1, and the power balance.
  const DeltaSteadyState s = conveyor_delta_steady(0.8, 0.6, 1, 1000, 0);
  ASSERT_TRUE(s.transport);
  EXPECT_NEAR(s.F, 200, 1e-9);
  EXPECT_NEAR(s.v_boy, 1.25, 1e-12);
  EXPECT_NEAR(s.v_c, 5, 1e-12);
  EXPECT_NEAR(s.v_bix, 1, 1e-15);                              // N = v_bix^2 / v_g^2 = 1
  EXPECT_NEAR(s.v_c * s.v_boy / (s.v_c + s.v_boy), 1, 1e-12);  // eq. 4.1: the belt delivers v_g
  EXPECT_NEAR(s.P_g, 1000, 1e-9);                              // zeta = 0: all power to the grains
  // Flux is linear in the power above the threshold zeta v_c^2, and zero below it.
  const double zeta = 10;
  const DeltaSteadyState a = conveyor_delta_steady(0.8, 0.6, 1, 500, zeta),
                         b = conveyor_delta_steady(0.8, 0.6, 1, 1000, zeta);
  EXPECT_NEAR(b.F - a.F, 500 / (25 * (1 - 0.64 / 0.8)), 1e-9);
  EXPECT_FALSE(conveyor_delta_steady(0.8, 0.6, 1, zeta * 25 * 0.99, zeta).transport);
  EXPECT_FALSE(conveyor_delta_steady(0.6, 0.6, 1, 1000, 0).transport);  // f <= 1 - eps^2
}

TEST(ConveyorMap, CaseDConvergesToTheClosedFormInEitherOrder) {
  for (const char* order : {"simultaneous", "velocity-first"}) {
    ConveyorMapParams p = table_4_2("D");
    p.order = order;
    for (const double F0 : {5.0, 50.0, 2000.0}) {
      const ConveyorMapResult r = conveyor_map(p, F0, 3.0);
      ASSERT_TRUE(r.converged) << order << " from " << F0;
      EXPECT_NEAR(r.history.back().F, 200, 1e-6) << order;
      EXPECT_NEAR(r.history.back().v_oy, 1.25, 1e-9) << order;
      EXPECT_NEAR(r.history.back().v_c, 5, 1e-9) << order;
    }
  }
}

TEST(ConveyorMap, CaseDLinearisationIsStableAndReal) {
  // Both eigenvalues inside the unit circle; grainlab finds them real (a monotone approach), where the
  // thesis describes an oscillating decay (docs/saltation.md).
  const ConveyorMapParams p = table_4_2("D");
  const ConveyorLinearization L = conveyor_linearization(p, {200, 1.25, 5, 1});
  for (const auto& e : L.eigenvalues) {
    EXPECT_LT(std::abs(e), 1.0);
    EXPECT_NEAR(e.imag(), 0, 1e-9);
  }
  EXPECT_LT(L.A11, 0);  // eq. 4.26's signs
  EXPECT_GT(L.B22, 0);
}

TEST(ConveyorMap, CaseEOscillatesBetweenTwoStates) {
  // With f falling steeply with impact speed the steady state near (F, v_oy) = (20, 1) repels and the map
  // ends on a 2-cycle (the thesis: "an oscillation between the two circled solutions").
  const ConveyorMapParams p = table_4_2("E");
  const DeltaSteadyState s = conveyor_delta_steady(p.f_at(1.0), p.eps, p.v_g, p.P_T, p.zeta);
  EXPECT_NEAR(s.F, 20, 0.5);
  EXPECT_NEAR(s.v_boy, 1.0, 0.03);
  const ConveyorMapResult r = conveyor_map(p, 50, 3, 5000);
  EXPECT_FALSE(r.converged);
  const auto& h = r.history;
  const MapState &a = h[h.size() - 1], &b = h[h.size() - 2], &c = h[h.size() - 3];
  EXPECT_NEAR(a.F, c.F, 1e-6 * a.F);  // period 2
  EXPECT_GT(std::abs(a.F - b.F), 0.05 * a.F);
}

TEST(ConveyorDistribution, Table41BeltSpeedsAndShapes) {
  // Spec [derived]: v_c ~ 14.1 (A, B), 13.6 (C); 20-30 iterations to 1 %.
  const DistributionResult a = conveyor_distribution(table_4_1("A"));
  const DistributionResult b = conveyor_distribution(table_4_1("B"));
  const DistributionResult c = conveyor_distribution(table_4_1("C"));
  ASSERT_TRUE(a.converged && b.converged && c.converged);
  EXPECT_NEAR(a.v_c, 14.1, 0.05);
  EXPECT_NEAR(b.v_c, 14.1, 0.05);
  EXPECT_NEAR(c.v_c, 13.6, 0.05);
  int to_one_percent = 0;
  while (a.residuals[static_cast<std::size_t>(to_one_percent)] > 0.01) ++to_one_percent;
  EXPECT_GE(to_one_percent, 15);
  EXPECT_LE(to_one_percent, 35);
  // A: a single peak; B: the same peak plus a low-velocity part in the first bin; C: the largest value in
  // the first bin (the ejecta term dominates there).
  auto peaks = [](const std::vector<double>& F) {
    int n = 0;
    for (std::size_t i = 1; i + 1 < F.size(); ++i) n += F[i] > F[i - 1] && F[i] > F[i + 1];
    return n;
  };
  EXPECT_EQ(peaks(a.F), 1);
  EXPECT_GT(b.F[0], 10 * a.F[0]);
  EXPECT_EQ(std::max_element(c.F.begin(), c.F.end()) - c.F.begin(), 0);
  // Power balance at the end.
  const DistributionSplashParams p = table_4_1("A");
  double power = p.zeta * a.v_c * a.v_c;
  for (std::size_t i = 0; i < a.F.size(); ++i)
    power += a.v_c * a.F[i] * a.v_c * a.mu[i] / (a.mu[i] + a.v_c) * p.dmu;
  EXPECT_NEAR(power, p.P_T, 1e-6 * p.P_T);
}

TEST(ConveyorDistribution, ANarrowStartThatKillsTheFluxIsReportedNotConverged) {
  // The spec's warning: a start concentrated below mu = 1. In CASE A the belt then runs near its speed
  // without grains (sqrt(P_T / zeta) = 141.4), the rebounds climb off the grid and F decays to the trivial
  // fixed point F = 0; that must be a failure, not a steady state. In CASE C the ejecta refill the low
  // bins and the same start reaches the steady state of the flat start (the thesis: independent of it).
  std::vector<double> narrow(40, 0.0);
  for (int i = 0; i < 4; ++i) narrow[static_cast<std::size_t>(i)] = 10;
  const DistributionResult a = conveyor_distribution(table_4_1("A"), 5000, 1e-10, narrow);
  EXPECT_FALSE(a.converged);
  EXPECT_NE(a.failure.find("died out"), std::string::npos) << a.failure;
  EXPECT_LT(a.iterations, 200);  // said early, not after the flux underflows
  const DistributionResult c_flat = conveyor_distribution(table_4_1("C"));
  const DistributionResult c = conveyor_distribution(table_4_1("C"), 5000, 1e-10, narrow);
  ASSERT_TRUE(c.converged) << c.failure;
  EXPECT_NEAR(c.v_c, c_flat.v_c, 1e-6 * c_flat.v_c);
  EXPECT_THROW(conveyor_distribution(table_4_1("C"), 10, 1e-10, std::vector<double>(7, 1.0)),
               std::invalid_argument);
}

// An option that would change nothing is refused by name: the conveyor's of the other kind of case
// (`--case A --F0 10` ran CASE A and ignored it), the wind's 2-D grid option without the 2-D grid. The
// start value that is wrong is the one named (`--v-oy0 0` was reported as --F0).
TEST(SaltationCommands, AnOptionThatChangesNothingHereIsRefusedByName) {
  cli_test::Dir d;
  const std::pair<const char*, const char*> refused[] = {
      {"--case A --F0 10", "--F0: 10: is for CASES D and E"},
      {"--case C --order velocity-first", "--order: velocity-first: is for CASES D and E"},
      {"--case E --start-below 0.3", "--start-below: 0.3: is for CASES A, B and C"},
      {"--case D --v-oy0 0", "--v-oy0: 0: must be > 0"},
      {"wind --case 1 --vx-min -50", "--vx-min: -50: is for the 2-D launch grid of --vx-bins"}};
  for (const auto& [args, message] : refused) {
    const std::string command = std::string(args).starts_with("wind") ? "saltation " : "saltation conveyor ";
    const cli_test::Outcome o = cli_test::grainlab(command + args, d.path);
    EXPECT_EQ(o.status, 2) << args;
    EXPECT_NE(o.err.find(message), std::string::npos) << o.err;
  }
}
