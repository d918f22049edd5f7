// Suite `hybrid` (issue #17): the 3-D hybrid ripple model of Huo et al. 2021, so far its pieces and its
// flux runs over a fixed flat bed. Checks: the drag law's limits, momentum and energy in mid-air
// collisions, the Lammel splash's numbers and sampled moments for both parameter sets, the grain-free wind
// (u+ = z+ and the log law), and Q*(S) against the law the paper fits (eq. 31, c_M = 2.3, mu_b = 0.61)
// within 25 %, with the threshold S_d fitted to the runs. docs/ripples.md, "3-D hybrid model".
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "collision.hpp"
#include "fluid.hpp"
#include "flux_model.hpp"
#include "lammel_splash.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

using namespace ripples::hybrid;
constexpr double kDeg = M_PI / 180;

void drag_checks(Report& rep) {
  const double re = 1e-6;
  rep.expect_near("hybrid/drag/stokes", "hybrid",
                  fluid::drag_coefficient(WindSpec::DragLaw::Huo2021, re) * re, 24, 0.05,
                  "C_d Re as Re -> 0: 24 (Stokes)");
  rep.expect_near("hybrid/drag/newton", "hybrid", fluid::drag_coefficient(WindSpec::DragLaw::Huo2021, 1e12),
                  0.5, 1e-3, "C_d as Re -> infinity: C_d_inf = 0.5");
}

void collision_checks(Report& rep) {
  Rng rng(7);
  double worst_momentum = 0, worst_energy = 0;
  for (int k = 0; k < 100000; ++k) {
    Vec3 v1{rng.normal(), rng.normal(), rng.normal()}, v2{rng.normal(), rng.normal(), rng.normal()};
    const Vec3 n = Vec3{rng.normal(), rng.normal(), rng.normal()}.normalized();
    const double m1 = rng.uniform(0.1, 10), m2 = rng.uniform(0.1, 10);
    const Vec3 p0 = m1 * v1 + m2 * v2;
    const double e0 = m1 * v1.squaredNorm() + m2 * v2.squaredNorm();
    if (!collide(v1, v2, m1, m2, n, {0.9, 0.4})) continue;
    worst_momentum = std::max(worst_momentum, (m1 * v1 + m2 * v2 - p0).norm() / p0.norm());
    worst_energy = std::max(worst_energy, (m1 * v1.squaredNorm() + m2 * v2.squaredNorm()) / e0);
  }
  rep.expect_below("hybrid/collisions/momentum", "hybrid", worst_momentum, 1e-12,
                   "largest relative momentum change over 1e5 random collisions (unequal masses)");
  rep.expect_below("hybrid/collisions/energy", "hybrid", worst_energy, 1.0,
                   "largest kinetic energy after / before over 1e5 random collisions");
}

void splash_checks(Report& rep, std::string& md) {
  const LammelCoefficients mono = lammel_coefficients(LammelParameters::paper2021(), 1, 1);
  rep.expect_near("hybrid/splash/paper2021/gamma", "hybrid", mono.gamma, 0.50, 0.005, "spec: gamma = 0.50");
  rep.expect_near("hybrid/splash/paper2021/restitution-10deg", "hybrid",
                  mean_restitution(mono, 1, 1, 10 * kDeg), 0.78, 0.005, "spec: e_bar(10 deg) = 0.78");
  rep.expect_near(
      "hybrid/splash/paper2021/ejecta-v100", "hybrid",
      ejecta_law(LammelParameters::paper2021(), mean_restitution(mono, 1, 1, 10 * kDeg), 5000, 1).mean_count,
      8, 1, "spec: N ~ 8 at v / sqrt(g d) = 100, 10 deg");
  md +=
      "| set | impact angle | mean rebound angle: analytic / sampled (deg) | ejecta per impact at v = 60 "
      "sqrt(g d): law / sampled |\n|---|---|---|---|\n";
  for (const char* set : {"paper2021", "lammel2017"}) {
    const LammelParameters p = LammelParameters::named(set);
    const LammelCoefficients c = lammel_coefficients(p, 1, 1);
    for (double theta_deg : {10.0, 30.0}) {
      const double theta = theta_deg * kDeg;
      Rng rng(5);
      const int n = 50000;
      double sum = 0, sum2 = 0, count = 0, count2 = 0;
      const EjectaLaw law = ejecta_law(p, mean_restitution(c, 1, 1, theta), 1800, 1);
      for (int k = 0; k < n; ++k) {
        const double a = rebound_angle(c, theta, rng.uniform());
        const double e = sample_ejecta_count(law, rng);
        sum += a, sum2 += a * a, count += e, count2 += e * e;
      }
      const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
      const double cmean = count / n, cse = std::sqrt(std::max(1e-12, count2 / n - cmean * cmean) / n);
      rep.expect_near(fmt::format("hybrid/splash/{}/rebound-angle-{:g}deg", set, theta_deg), "hybrid",
                      mean / kDeg, mean_rebound_angle(c, theta) / kDeg, 4 * se / kDeg,
                      "sampled mean rebound angle vs eq. 9's mean (4 standard errors)");
      rep.expect_near(fmt::format("hybrid/splash/{}/ejecta-{:g}deg", set, theta_deg), "hybrid", cmean,
                      law.mean_count, 4 * cse, "sampled ejecta count vs eq. 15 (4 standard errors)");
      md += fmt::format("| {} | {:g} | {:.2f} / {:.2f} | {:.3f} / {:.3f} |\n", set, theta_deg,
                        mean_rebound_angle(c, theta) / kDeg, mean / kDeg, law.mean_count, cmean);
    }
  }
  md += "\n";
}

void wind_checks(Report& rep, const FluxOptions& o) {
  const CleanWind w = clean_wind(o);
  const double nu = o.viscosity, us = o.u_star;
  auto u_plus = [&](double z_plus) {  // interpolated in the column
    const double z = z_plus * nu / us;
    std::size_t k = 0;
    while (k + 2 < w.z.size() && w.z[k + 1] < z) ++k;
    const double a = (z - w.z[k]) / (w.z[k + 1] - w.z[k]);
    return (w.u[k] * (1 - a) + w.u[k + 1] * a) / us;
  };
  rep.expect_near("hybrid/wind/viscous-sublayer", "hybrid", u_plus(0.5), 0.5, 0.01,
                  "grain-free wind: u+ at z+ = 0.5 (u+ = z+ in the viscous sublayer)");
  rep.expect_near("hybrid/wind/log-law", "hybrid", u_plus(2000) - u_plus(200), std::log(10.0) / 0.42, 0.05,
                  "grain-free wind: u+(2000) - u+(200) = ln(10) / kappa, kappa = 0.42");
}

// The dynamic threshold S_d as the paper defines it, where transport stops: Q* of the two weakest runs that
// carried sand, extrapolated linearly to zero (eq. 31 is linear in S near S_d). (A least-squares fit of
// S_d to all runs ran off to S_d -> 0: the runs' Q* rises faster with S than eq. 31 lets it.)
double fit_threshold(std::vector<FluxResult> runs) {
  std::sort(runs.begin(), runs.end(),
            [](const FluxResult& a, const FluxResult& b) { return a.shields < b.shields; });
  if (runs.size() < 2) return runs.empty() ? 0 : runs[0].shields;
  const FluxResult &a = runs[0], &b = runs[1];
  const double slope = (b.mass_flux_star - a.mass_flux_star) / (b.shields - a.shields);
  return slope > 0 ? std::max(0.0, a.shields - a.mass_flux_star / slope) : a.shields;
}

void flux_checks(Report& rep, const FluxOptions& base, bool quick, const SuiteOptions& so, std::string& md) {
  const std::vector<double> ustars =
      quick ? std::vector<double>{26, 30, 40, 50} : std::vector<double>{24, 26, 30, 35, 40, 50, 60, 70};
  std::vector<FluxResult> runs;
  for (double u : ustars) {
    FluxOptions o = base;
    o.u_star = u;
    if (so.log) so.log(fmt::format("hybrid flux run: u* = {} cm/s, {} t*", u, o.duration));
    runs.push_back(run_flux(o));
  }
  std::vector<FluxResult> moving;
  for (const FluxResult& r : runs)
    if (r.mass_flux_star > 0) moving.push_back(r);
  const double sd = fit_threshold(moving);
  md += fmt::format(
      "Flux runs: {} d x {} d periodic, flat fixed bed, s = {:.0f}, Ga = {:.1f}, {} t* averaged from {}; "
      "splash {}. S_d, where Q* extrapolates to zero from the two weakest runs: {:.4f}.\n\n| u* (cm/s) | S | "
      "Q* | eq. 31 | ratio | airborne | "
      "u* at the bed | impact speed / angle | grain-steps/s |\n|---|---|---|---|---|---|---|---|---|\n",
      base.length, base.width, runs.front().s, runs.front().galileo, base.duration, base.average_from,
      base.splash, sd);
  PlotSpec plot{"hybrid_flux_law.png", "Q*(S): hybrid flux runs and eq. 31", "S", "Q*", false, {}};
  PlotSpec::Series measured{"hybrid model", "points", {}, {}, {}},
      law{"eq. 31, measured S_d", "line", {}, {}, {}};
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const FluxResult& r = runs[k];
    const double predicted = flux_law(r.shields, sd);
    md += fmt::format(
        "| {:g} | {:.4f} | {:.5f} | {:.5f} | {:.2f} | {:.0f} | {:.1f} | {:.0f} cm/s at {:.0f} deg | "
        "{:.3g} |\n",
        ustars[k], r.shields, r.mass_flux_star, predicted, predicted > 0 ? r.mass_flux_star / predicted : NAN,
        r.airborne, r.u_star_bed, r.mean_impact_speed, r.mean_impact_angle_deg,
        r.wall_seconds > 0 ? static_cast<double>(r.grain_steps) / r.wall_seconds : 0.0);
    measured.x.push_back(r.shields), measured.y.push_back(r.mass_flux_star);
    if (r.mass_flux_star > 0 && predicted > 0)
      rep.expect_near(fmt::format("hybrid/flux/S={:.4f}", r.shields), "hybrid", r.mass_flux_star / predicted,
                      1, 0.25, "Q* / eq. 31 with the measured S_d (c_M = 2.3, mu_b = 0.61, kappa = 0.42)");
  }
  for (int k = 0; k <= 50; ++k) {
    const double s = sd + (runs.back().shields * 1.1 - sd) * k / 50.0;
    law.x.push_back(s), law.y.push_back(flux_law(s, sd));
  }
  plot.series = {measured, law};
  rep.plots.push_back(plot);
  md += "\n";
}

}  // namespace

void run_hybrid_suite(Report& rep, const SuiteOptions& so) {
  std::string md = "# 3-D hybrid model (Huo et al. 2021): pieces and flux runs\n\n";
  drag_checks(rep);
  collision_checks(rep);
  splash_checks(rep, md);
  FluxOptions base;
  base.duration = so.quick ? 1200 : 6000, base.average_from = so.quick ? 600 : 2000;
  wind_checks(rep, base);
  flux_checks(rep, base, so.quick, so, md);
  md +=
      "Not built yet: the bed (height field, repose, polydisperse layer), ripple runs, the measured splash, "
      "MPI "
      "(docs/ripples.md).\n";
  rep.markdown.push_back(md);
}

}  // namespace grainlab::validation
