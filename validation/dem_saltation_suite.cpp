// Suite `dem-saltation` (issue #18): saltation from first principles on a periodic DEM bed under a wind
// the grains slow down. Checks: the momentum the wind loses is what the grains receive, the wind's stress
// partition, and (reported against the literature) Q(u*) near u*^2, impact speeds nearly independent of
// u*, results independent of the reduced contact stiffness, a threshold where transport dies, and the
// Ch. IV model given the splash the DEM measured. docs/saltation.md, "DEM saltation".
#include <fmt/format.h>

#include <cmath>

#include "dem_saltation.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

struct Run {
  std::string label;
  DemSaltationOptions o;
  DemSaltationResult r;
};

DemSaltationOptions base_options(bool quick) {
  DemSaltationOptions o;
  // Quick: a narrow bed, but run into the steady state. Saltation started by the kick dies back to a
  // third of its steady flux by ~0.4 s and regrows until ~0.9 s at u* = 35 (series.csv); a window from
  // 0.3 to 0.6 s (the earlier quick form) measured that transient: impact speeds 23 cm/s at u* = 35
  // against 54 on the mid-size bed, so its u* comparison meant nothing.
  if (quick) o.columns = 100, o.layers = 8, o.duration = 1.4, o.average_from = 0.7;
  return o;
}

Run run(const std::string& label, DemSaltationOptions o, const SuiteOptions& so) {
  if (so.log)
    so.log(fmt::format("{}: u* = {} cm/s, k_n = {:g} dyn/cm, {} x {} grains, {} s", label, o.u_star, o.k_n,
                       o.columns, o.layers, o.duration));
  o.distributed = false;  // each run on one process; the suite's runs are independent
  Run r{label, o, run_dem_saltation(o)};
  if (so.log)
    so.log(fmt::format("  Q {:.4g} g/(cm s), u*_eff {:.1f} cm/s, {:.0f} s", r.r.mass_flux.mean,
                       r.r.u_star_eff.mean, r.r.wall_seconds));
  return r;
}

void balance_checks(Report& rep, const Run& r) {
  const double rho_u2 = r.o.fluid_density * r.o.u_star * r.o.u_star;
  rep.expect_near(
      fmt::format("dem-saltation/{}/momentum-balance", r.label), "native",
      r.r.grain_momentum_gain / r.r.wind_momentum_loss, 1.0, 0.01,
      fmt::format("momentum the grains received by drag / momentum the wind lost ({:.4g} / {:.4g} "
                  "dyn/cm^2; rho u*^2 = {:.4g}; the two differ by {:.3g} per wind update)",
                  r.r.grain_momentum_gain, r.r.wind_momentum_loss, rho_u2, r.r.coupling_lag));
  rep.expect_near(fmt::format("dem-saltation/{}/stress-partition", r.label), "native", r.r.stress_partition,
                  1.0, 0.01, "(fluid + grain-borne stress) / rho u*^2 one diameter above the bed");
}

std::string row(const Run& r) {
  const DemSaltationResult& x = r.r;
  return fmt::format(
      "| {} | {:g} | {:g} | {:.4g} [{:.4g}, {:.4g}] | {:.1f} | {:.0f} | {:.1f} | {:.3f} / {:.2f} | {:.0f} at "
      "{:.0f} | {} | {:.4g} | {:.1f} % |\n",
      r.label, r.o.u_star, r.o.k_n, x.mass_flux.mean, x.mass_flux.lo, x.mass_flux.hi, x.u_star_eff.mean,
      x.airborne.mean, x.transport_velocity, x.salton_hop_height.mean, x.salton_hop_length.mean,
      x.salton_impact_speed.mean, x.salton_impact_angle.mean, x.impacts.size(),
      x.model.ran ? x.model.mass_flux : NAN, 100 * x.wind_seconds / x.wall_seconds);
}

// Q ~ u*^n between the lowest and highest u* that carried sand, against Ho et al. 2011's law for erodible
// beds, Q ~ u*^2 - u_t^2 with u_t Bagnold's impact threshold: its exponent between the same two u*. The
// tolerance is 0.5 and the measured exponent's own 95 % interval (from the two fluxes') in quadrature.
void flux_law(Report& rep, const std::vector<Run>& by_ustar, double impact_threshold, std::string& md) {
  const Run *lo = nullptr, *hi = nullptr;
  for (const Run& r : by_ustar)
    if (r.r.mass_flux.mean > 0) (lo ? hi : lo) = &r, hi = lo == &r ? hi : &r;
  if (!lo || !hi || lo == hi) return;
  const double span = std::log(hi->o.u_star / lo->o.u_star);
  const double n = std::log(hi->r.mass_flux.mean / lo->r.mass_flux.mean) / span;
  const double ut2 = impact_threshold * impact_threshold;
  const double n_ho =
      std::log((hi->o.u_star * hi->o.u_star - ut2) / (lo->o.u_star * lo->o.u_star - ut2)) / span;
  const double dn = std::hypot(hi->r.mass_flux.half_width() / hi->r.mass_flux.mean,
                               lo->r.mass_flux.half_width() / lo->r.mass_flux.mean) /
                    span;
  rep.expect_near(
      "dem-saltation/flux-exponent", "native", n, n_ho, std::hypot(0.5, dn),
      fmt::format("Q ~ u*^n between u* = {:g} and {:g} cm/s (+- {:.2f} from the fluxes' intervals) against "
                  "Ho et al. 2011's Q ~ u*^2 - u_t^2 with u_t = {:.1f} cm/s (pure u*^2: 2; Bagnold: 3)",
                  lo->o.u_star, hi->o.u_star, dn, impact_threshold));
  const double ratio = hi->r.salton_impact_speed.mean / lo->r.salton_impact_speed.mean;
  rep.expect_near(
      "dem-saltation/impact-speed-independent-of-ustar", "native", ratio, 1.0, 0.2,
      fmt::format("mean impact speed of hops above 5 d at u* = {:g} over u* = {:g} (Creyssels et al. "
                  "2009: nearly independent of u*)",
                  hi->o.u_star, lo->o.u_star));
  const double v_ratio = hi->r.transport_velocity / lo->r.transport_velocity;
  rep.expect_near(
      "dem-saltation/grain-velocity-independent-of-ustar", "native", v_ratio, 1.0, 0.2,
      fmt::format(
          "mean downwind velocity of the grains above 1 d (their flux / their mass) at u* = {:g} over "
          "u* = {:g} (Creyssels et al. 2009, Duran et al. 2012: independent of u*; 20 %)",
          hi->o.u_star, lo->o.u_star));
  md += fmt::format(
      "Flux exponent between u* = {:g} and {:g} cm/s: **{:.2f}** +- {:.2f} (Ho et al. 2011's form: "
      "{:.2f}); impact speed ratio {:.2f}; grain velocity ratio {:.2f}.\n\n",
      lo->o.u_star, hi->o.u_star, n, dn, n_ho, ratio, v_ratio);
}

// Bagnold's focus: the height where the wind profiles of different u* come closest together.
void focus(const std::vector<Run>& by_ustar, std::string& md) {
  if (by_ustar.size() < 2) return;
  double best = INFINITY, at = 0, speed = 0;
  const std::vector<double>& z = by_ustar.front().r.z;
  for (std::size_t k = 0; k < z.size(); ++k) {
    if (z[k] <= by_ustar.front().o.diameter) continue;
    double lo = INFINITY, hi = -INFINITY;
    for (const Run& r : by_ustar)
      if (k < r.r.wind.size()) lo = std::min(lo, r.r.wind[k]), hi = std::max(hi, r.r.wind[k]);
    if (hi - lo < best) best = hi - lo, at = z[k], speed = 0.5 * (lo + hi);
  }
  md += fmt::format(
      "Focus of the wind profiles: closest at z = {:.3f} cm above the bed, u = {:.0f} cm/s (spread "
      "{:.1f} cm/s; Bagnold's focus for sand: a few mm).\n\n",
      at, speed, best);
}

void stiffness_checks(Report& rep, const Run& base, const std::vector<Run>& varied) {
  for (const Run& v : varied) {
    const double half = std::hypot(base.r.mass_flux.half_width(), v.r.mass_flux.half_width());
    rep.expect_near(
        fmt::format("dem-saltation/stiffness-{:g}", v.o.k_n), "native", v.r.mass_flux.mean,
        base.r.mass_flux.mean, half,
        fmt::format("Q with k_n = {:g} against k_n = {:g} (within the two 95 % intervals combined)", v.o.k_n,
                    base.o.k_n));
  }
}

void plots(Report& rep, const std::vector<Run>& by_ustar) {
  PlotSpec q{"dem_saltation_flux.png",
             "DEM saltation: mass flux against u*",
             "u* (cm/s)",
             "Q (g/(cm s))",
             false,
             {}};
  PlotSpec::Series dem{"DEM (95 % interval)", "linepoints", {}, {}, {}},
      model{"Ch. IV model, DEM's own splash", "points", {}, {}, {}},
      bagnold{"Bagnold, C = 1.8", "dashed", {}, {}, {}};
  for (const Run& r : by_ustar) {
    dem.x.push_back(r.o.u_star), dem.y.push_back(r.r.mass_flux.mean),
        dem.err.push_back(r.r.mass_flux.half_width());
    if (r.r.model.ran) model.x.push_back(r.o.u_star), model.y.push_back(r.r.model.mass_flux);
    bagnold.x.push_back(r.o.u_star);
    bagnold.y.push_back(1.8 * r.o.fluid_density / 981 * std::pow(r.o.u_star, 3));
  }
  q.series = {dem, model, bagnold};
  rep.plots.push_back(q);
}

}  // namespace

void run_dem_saltation_suite(Report& rep, const SuiteOptions& so) {
  const DemSaltationOptions base = base_options(so.quick);
  const std::vector<double> ustars =
      so.quick ? std::vector<double>{35, 50} : std::vector<double>{20, 25, 30, 35, 40, 50, 60};
  const double reference_ustar = so.quick ? 50 : 40;
  std::vector<Run> by_ustar, varied;
  for (double u : ustars) {
    DemSaltationOptions o = base;
    o.u_star = u;
    by_ustar.push_back(run(fmt::format("u*={:g}", u), o, so));
  }
  const Run* reference = nullptr;
  for (const Run& r : by_ustar)
    if (r.o.u_star == reference_ustar) reference = &r;
  for (double f : {0.5, 2.0}) {
    DemSaltationOptions o = base;
    o.u_star = reference_ustar, o.k_n = base.k_n * f;
    varied.push_back(run(fmt::format("u*={:g},k_n*{:g}", reference_ustar, f), o, so));
  }
  std::string md = fmt::format(
      "# DEM saltation\n\nA periodic bed of {} x {} grains (d = {} cm +- {:.0f} %, quartz in air), {} s of "
      "which the "
      "last {} s are averaged. Hops above 5 d count as saltation.\n\n| run | u* | k_n | Q (g/(cm s)) | "
      "u*_eff | "
      "airborne | grain velocity above 1 d (cm/s) | salton hop height / length (cm) | impact speed (cm/s) at "
      "angle (deg) | impacts | Q, Ch. IV model with this splash | wind share "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      base.columns, base.layers, base.diameter, 100 * base.polydispersity, base.duration,
      base.duration - base.average_from);
  for (const Run& r : by_ustar) md += row(r), balance_checks(rep, r);
  for (const Run& r : varied) md += row(r), balance_checks(rep, r);
  md += "\n";
  // Bagnold's fluid threshold A sqrt((rho_s - rho) g d / rho) with A = 0.1, and the impact threshold ~0.8 of
  // it.
  const double fluid_t =
      0.1 * std::sqrt((base.grain_density - base.fluid_density) * 981 * base.diameter / base.fluid_density);
  flux_law(rep, by_ustar, 0.8 * fluid_t, md);
  focus(by_ustar, md);
  if (reference) stiffness_checks(rep, *reference, varied);
  // The threshold: the lowest u* that still carried sand in the window, beside Bagnold's.
  double dead = 0;
  for (const Run& r : by_ustar)
    if (r.r.airborne.mean < 0.5) dead = std::max(dead, r.o.u_star);
  md += fmt::format(
      "Transport died (fewer than half a grain airborne) at u* <= {:g} cm/s in this scan; Bagnold's fluid "
      "threshold {:.1f} cm/s, impact threshold ~{:.1f} cm/s.\n",
      dead, fluid_t, 0.8 * fluid_t);
  rep.markdown.push_back(md);
  plots(rep, by_ustar);
}

}  // namespace grainlab::validation
