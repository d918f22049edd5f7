// Suite `saltation`: the thesis's Ch. IV models against its tables. The conveyor-belt map's steady state
// (Table 4.2 D), the distribution splash (Table 4.1), and the wind-driven model for Table 4.3's splash
// functions: its exact identities, Table 4.5 (u*_eff), Table 4.4 (peak heights), CASE 1's text numbers and
// the flux law. Every number the thesis prints is a check; where grainlab disagrees the check fails and
// docs/saltation.md says what is known about why.
#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cmath>

#include "conveyor.hpp"
#include "saltation_heights.hpp"
#include "splash_file.hpp"
#include "study.hpp"
#include "suites.hpp"
#include "transient.hpp"
#include "wind_model.hpp"

namespace grainlab::validation {

namespace {

using namespace grainlab::saltation;

// Table 4.5, u*_eff (cm/s) at the three u* of CASES 1-6 (table_4_3_ustars) and CASE 7 (50, 100, 125).
constexpr double kTable45[7][3] = {{33.1, 29.0, 24.8}, {25.1, 20.1, 13.9}, {35.0, 30.6, 24.2},
                                   {26.4, 24.6, 20.9}, {40.6, 35.7, 31.1}, {28.0, 20.4, 12.1},
                                   {25.6, 25.1, 21.5}};
// Table 4.4, peak heights (cm) of flux / kinetic-energy flux / drag at the same u*. CASE 3's row is printed
// for u* = 35, 50, 75 (Table 4.3 lists 35, 75, 125): the suite compares the rows by position and says so.
constexpr double kTable44[6][3][3] = {
    {{3.0, 3.0, 1.2}, {3.0, 3.0, 1.6}, {3.4, 5.0, 3.0}}, {{1.0, 2.0, 0.2}, {1.6, 2.5, 1.0}, {1.8, 4.0, 1.6}},
    {{0.6, 1.5, 0.2}, {1.1, 3.5, 0.2}, {0.6, 2.5, 0.2}}, {{0.6, 3.4, 0.2}, {1.4, 3.4, 0.2}, {2.0, 5.0, 0.2}},
    {{0.8, 2.0, 0.6}, {0.8, 2.0, 0.6}, {1.4, 3.0, 1.2}}, {{1.6, 2.0, 0.2}, {1.0, 2.0, 0.2}, {1.0, 4.0, 1.0}}};
const char* const kPeakNames[3] = {"flux", "energy-flux", "drag"};

struct Cell {
  int case_number = 0;
  double u_star = 0;
  WindModelResult r;
  double peaks[3] = {0, 0, 0};  // flux, kinetic-energy flux, drag
  WindModelOptions options;
};

// m times the integral of the horizontal number-flux profile: the mass flux computed a second way.
double integrated_mass_flux(const WindModelResult& r, double mass) {
  double q = 0;
  for (std::size_t k = 0; k < r.y.size(); ++k) q += r.number_flux[k] * r.dy[k];
  return q * mass;
}

void conveyor_checks(Report& rep, std::string& md) {
  md += "## Conveyor-belt model\n\n| check | grainlab | thesis |\n|---|---|---|\n";
  for (const std::string order : {"simultaneous", "velocity-first"}) {
    ConveyorMapParams p = table_4_2("D");
    p.order = order;
    const ConveyorMapResult m = conveyor_map(p, 50, 3);
    const MapState& s = m.history.back();
    rep.expect_near("saltation/conveyor/D-" + order + "/F", "conveyor", s.F, 200, 1e-6,
                    "Table 4.2 D: the map (eq. 4.23) converges to F = 200");
    rep.expect_near("saltation/conveyor/D-" + order + "/v_oy", "conveyor", s.v_oy, 1.25, 1e-8,
                    "Table 4.2 D: v_oy = 1.25");
    rep.expect_near("saltation/conveyor/D-" + order + "/v_c", "conveyor", s.v_c, 5, 1e-8,
                    "Table 4.2 D: v_c = 5");
    md +=
        fmt::format("| D ({}), (F, v_oy, v_c) after {} steps | ({:.6g}, {:.6g}, {:.6g}) | (200, 1.25, 5) |\n",
                    order, m.iterations, s.F, s.v_oy, s.v_c);
  }
  // Eqs 4.3-4.5: the closed form balances power and replaces each grain exactly once.
  const DeltaSteadyState d = conveyor_delta_steady(0.8, 0.6, 1, 1000, 0);
  rep.expect_near("saltation/conveyor/delta-replacement", "conveyor", d.v_bix, 1, 1e-12,
                  "eqs 4.3: the impact speed equals v_g (N = 1)");
  rep.expect_near("saltation/conveyor/delta-power", "conveyor", d.F * d.v_c * d.v_bix, 1000, 1e-9,
                  "eq. 4.5 with zeta = 0: the belt's power all goes to the grains, P_T = F v_c v_bix");
  for (const auto& [name, v_c] : {std::pair<std::string, double>{"A", 14.1}, {"C", 13.6}}) {
    const DistributionResult r = conveyor_distribution(table_4_1(name));
    rep.expect_near("saltation/conveyor/" + name + "-v_c", "conveyor", r.v_c, v_c, 0.05,
                    "Table 4.1 " + name +
                        ": belt speed of the distribution splash's fixed point (spec, "
                        "derived; to its rounding)");
    md += fmt::format("| Table 4.1 {}: v_c | {:.3f} | {} (derived) |\n", name, r.v_c, v_c);
  }
  md += "\n";
}

std::vector<Cell> run_cells(const std::vector<int>& cases, const SuiteOptions& o) {
  std::vector<Cell> cells;
  std::size_t total = cases.size() * 3, done = 0;
  for (int c : cases)
    for (double u : table_4_3_ustars(c)) {
      WindModelOptions opt;
      opt.u_star = u;
      Cell cell{c, u, solve_wind_model(opt, table_4_3(c)), {}, opt};
      const double from = 2 * cell.options.grain.radius;  // one grain diameter
      cell.peaks[0] = peak_height(cell.r.y, cell.r.number_flux, from);
      cell.peaks[1] = peak_height(cell.r.y, cell.r.energy_flux, from);
      cell.peaks[2] = peak_height(cell.r.y, cell.r.drag_resolved, from);
      cells.push_back(std::move(cell));
      if (o.progress) o.progress(++done, total);
    }
  return cells;
}

// CASE 7: the sand-gun splash (Tables 3.11-3.12) for its coarse sand (d = 0.078 cm), at 50, 100, 125 cm/s.
std::vector<Cell> run_case7(const SuiteOptions& o) {
  std::vector<Cell> cells;
  for (double u : {50.0, 100.0, 125.0}) {
    WindModelOptions opt;
    opt.u_star = u, opt.grain.radius = 0.039;
    cells.push_back(Cell{7, u, solve_wind_model(opt, kernel_of(sand_gun_splash(), opt)), {}, opt});
    if (o.progress) o.progress(cells.size(), 3);
  }
  return cells;
}

void identity_checks(Report& rep, const Cell& c) {
  const WindModelOptions& opt = c.options;
  const double rho = opt.fluid.density, tau0 = rho * c.u_star * c.u_star;
  const std::string id = fmt::format("saltation/case-{}/u{:g}", c.case_number, c.u_star);
  rep.expect_below(id + "/converged", "wind-model", c.r.converged ? 0 : 1, 0,
                   fmt::format("the fixed point is reached ({} iterations, {:.1f} s){}", c.r.iterations,
                               c.r.wall_seconds, c.r.failure.empty() ? "" : ": " + c.r.failure));
  if (!c.r.failure.empty()) return;  // no state to check identities on
  const double stress = rho * (c.u_star * c.u_star - c.r.u_star_eff * c.r.u_star_eff);
  rep.expect_below(
      id + "/identity-stress", "wind-model", std::abs(c.r.grain_stress - stress) / tau0, 0.01,
      "u*_eff^2 = u*^2 - tau_g / rho with tau_g = sum m F dv (v_ix - v_ox), relative to rho u*^2 "
      "(Newton's third law between the grains' drag and the air's body force)");
  const double q2 = integrated_mass_flux(c.r, opt.grain.mass());
  rep.expect_below(id + "/identity-mass-flux", "wind-model", std::abs(c.r.mass_flux - q2) / c.r.mass_flux,
                   0.01,
                   "Q = sum m F dv L equals m times the integral of the horizontal number-flux profile");
}

// The thesis: "consistent with the mass flux being related to the square of the wind-shear velocity, as
// advocated by Ungar and Haff (1986) ... inconsistent with the cubic relations". Two readings are checked.
// The issue's: Q ~ u*^n with n within 0.3 of 2 over the case's three u*. And Ungar & Haff's law,
// Q ~ u*^2 - u*_t^2: Q linear in u*^2, its secant slopes' ratio nearer 1 than halfway (on log axes) to the
// ratio Q ~ u*^3 gives at the same u*. Beside them, the exponent of the grain-borne stress
// tau_g = rho (u*^2 - u*_eff^2) that the thesis's own Table 4.5 implies: Q / tau_g is the mean hop length
// per unit of momentum a grain takes from the wind, nearly fixed by the steady state.
void flux_law_checks(Report& rep, const std::array<const Cell*, 3>& run, std::string& md) {
  std::vector<double> u, q, tau_thesis;
  const int case_number = run[0]->case_number;
  for (std::size_t k = 0; k < run.size(); ++k) {
    u.push_back(run[k]->u_star), q.push_back(run[k]->r.mass_flux);
    const double ue = kTable45[case_number - 1][k];
    tau_thesis.push_back(u.back() * u.back() - ue * ue);
  }
  const FluxGrowth g = flux_growth(u, q), thesis = flux_growth(u, tau_thesis);
  rep.expect_near(fmt::format("saltation/flux-exponent/case-{}", case_number), "wind-model", g.exponent, 2,
                  0.3,
                  "mass flux ~ u*^n over the case's three u*: n within 0.3 of 2 (the issue's reading; the "
                  "thesis's own Table 4.5 implies more, docs/saltation.md)");
  const double band = 0.5 * std::log(g.cube_slope_ratio);
  rep.expect_below(
      fmt::format("saltation/flux-square-law/case-{}", case_number), "wind-model",
      std::abs(std::log(g.square_slope_ratio)), band,
      fmt::format("Q linear in u*^2 (Ungar & Haff, which the thesis cites): |ln| of the ratio of "
                  "the secant slopes dQ/d(u*^2) below half ln {:.2f}, the ratio of Q ~ u*^3",
                  g.cube_slope_ratio));
  const bool thesis_flux = tau_thesis[0] > 0;  // (CASE 3 at 35 cm/s: u*_eff = u*, no flux to take a log of)
  md += fmt::format(
      "| {} | {:g}, {:g}, {:g} | {:.2f} | {} | {:.2f} | {:.2f} | {:.2f} |\n", case_number, u[0], u[1], u[2],
      g.exponent,
      thesis_flux ? fmt::format("{:.2f}", thesis.exponent) : fmt::format("none: no flux at {:g}", u[0]),
      g.square_slope_ratio, thesis.square_slope_ratio, g.cube_slope_ratio);
}

void table_checks(Report& rep, const std::vector<Cell>& cells, std::string& md) {
  std::string flux_md =
      "## The flux law\n\n| CASE | u* | exponent of Q | exponent of the thesis's tau_g (Table 4.5) | "
      "dQ/d(u*^2) last / first | the same for the thesis's tau_g | for Q ~ u*^3 "
      "|\n|---|---|---|---|---|---|---|\n";
  md +=
      "## Table 4.5: u*_eff (cm/s)\n\n| CASE | u* | thesis | grainlab | difference | iterations | wall (s) "
      "| Q (g/(cm s)) |\n|---|---|---|---|---|---|---|---|\n";
  double wall = 0;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    const double ref = kTable45[c.case_number - 1][i % 3];
    rep.expect_near(fmt::format("saltation/table-4.5/case-{}/u{:g}", c.case_number, c.u_star), "wind-model",
                    c.r.u_star_eff, ref, 0.1 * ref, "Table 4.5 within 10 % (docs/saltation.md: why not)");
    if (c.r.failure.empty())
      md += fmt::format("| {} | {:g} | {} | {:.1f} | {:+.0f} % | {} | {:.1f} | {:.3g} |\n", c.case_number,
                        c.u_star, ref, c.r.u_star_eff, 100 * (c.r.u_star_eff / ref - 1), c.r.iterations,
                        c.r.wall_seconds, c.r.mass_flux);
    else
      md += fmt::format("| {} | {:g} | {} | no steady state | - | {} | {:.1f} | - |\n", c.case_number,
                        c.u_star, ref, c.r.iterations, c.r.wall_seconds);
    wall += c.r.wall_seconds;
    if (i % 3 == 2) {
      const Cell &a = cells[i - 2], &b = cells[i - 1];
      // Only states count: a run without one has no u*_eff to order.
      const bool states = a.r.failure.empty() && b.r.failure.empty() && c.r.failure.empty();
      const bool falls = states && a.r.u_star_eff > b.r.u_star_eff && b.r.u_star_eff > c.r.u_star_eff;
      rep.expect_below(fmt::format("saltation/table-4.5/case-{}/decreasing", c.case_number), "wind-model",
                       falls ? 0 : 1, 0, "u*_eff falls strictly as u* rises (the thesis, every case)");
      if (states) {
        flux_law_checks(rep, {&a, &b, &c}, flux_md);
      } else {
        for (const char* law : {"flux-exponent", "flux-square-law"})
          rep.expect_below(fmt::format("saltation/{}/case-{}", law, c.case_number), "wind-model", 1, 0,
                           "the flux law needs a steady state at all three u*");
      }
    }
  }
  md += fmt::format("\nAll {} runs took {:.1f} s on one core.\n\n", cells.size(), wall);
  md += flux_md + "\n";
  md +=
      "## Table 4.4: peak heights (cm) of flux / kinetic-energy flux / drag\n\n| CASE | u* | thesis | "
      "grainlab "
      "|\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const Cell& c = cells[i];
    if (c.case_number > 6) continue;  // Table 4.4 has CASES 1-6
    const double* ref = kTable44[c.case_number - 1][i % 3];
    md += fmt::format("| {} | {:g} | {} / {} / {} | {:.2f} / {:.2f} / {:.2f} |\n", c.case_number, c.u_star,
                      ref[0], ref[1], ref[2], c.peaks[0], c.peaks[1], c.peaks[2]);
    const std::string id = fmt::format("saltation/table-4.4/case-{}/u{:g}", c.case_number, c.u_star);
    // 6 % tolerance: the height grid's node spacing.
    const bool ordered = c.peaks[1] >= c.peaks[0] / 1.07 && c.peaks[0] >= c.peaks[2] / 1.07;
    rep.expect_below(id + "/ordered", "wind-model", ordered ? 0 : 1, 0,
                     "peak heights ordered kinetic-energy flux >= flux >= drag, as in Table 4.4");
    for (int q = 0; q < 3; ++q)
      rep.expect_near(fmt::format("{}/{}-peak", id, kPeakNames[q]), "wind-model", c.peaks[q], ref[q],
                      0.25 * ref[q], "Table 4.4 peak height within 25 %");
  }
  md +=
      "\nCASE 3's row of Table 4.4 is printed for u* = 35, 50, 75 cm/s while Table 4.3 lists 35, 75, 125; "
      "the rows are compared by position.\n\n";
}

void case1_text_checks(Report& rep, const Cell& c, std::string& md) {
  // The checks take the means per launch (per hop); the means over the grains in the air, which the text
  // may have meant, are shown beside them (docs/saltation.md).
  const struct {
    const char* name;
    double value, ref, airborne;
  } rows[] = {{"hop-height", c.r.mean_hop_height, 3.5, c.r.airborne_hop_height},
              {"hop-length", c.r.mean_hop_length, 40, c.r.airborne_hop_length},
              {"impact-vx", c.r.mean_impact_vx, 320, NAN},
              {"impact-vy", -c.r.mean_impact_vy, 70, NAN}};
  md +=
      "## CASE 1 at u* = 35 cm/s against the text\n\n| quantity | thesis | grainlab, per hop | grainlab, "
      "over the grains in the air |\n|---|---|---|---|\n";
  for (const auto& row : rows) {
    rep.expect_near(fmt::format("saltation/case-1/u35/{}", row.name), "wind-model", row.value, row.ref,
                    0.2 * row.ref, "the Ch. IV text's CASE 1 means, within 20 %");
    md += fmt::format("| {} | {} | {:.1f} | {} |\n", row.name, row.ref, row.value,
                      std::isnan(row.airborne) ? std::string("-") : fmt::format("{:.1f}", row.airborne));
  }
  md += "\n";
}

// CASE 1's spreads. Of the launch distribution (Fig. 4.11): "The half-widths of the distributions are about
// 45 cm/sec, somewhat larger than the intrinsic half-width of the gaussian splash function, 35 cm/sec"; the
// thesis calls c2 (the Gaussian's sigma) its half-width, so the check reads the standard deviation and the
// half width at half maximum is shown beside it. Of the hops: after giving CASE 1's mean hop height, length
// and impact velocities, the text says that "in going from u* = 35 to 125, the half-widths of the
// distributions of these quantities increase by ten to thirty percent" (the stretching of the
// trajectories at the focus): those four spreads, over the hops, must grow by 10-30 %.
void case1_spread_checks(Report& rep, const Cell& low, const Cell& high, std::string& md) {
  const LaunchSpread &a = low.r.launch_vy, &b = high.r.launch_vy;
  rep.expect_near("saltation/case-1/u35/launch-half-width", "wind-model", a.sd, 45, 0.2 * 45,
                  fmt::format("CASE 1's launch v_oy distribution at u* = 35: s.d. {:.1f} cm/s (half width at "
                              "half maximum {:.1f}) against the text's ~45 (c2 = 35), within 20 %",
                              a.sd, a.half_width));
  md += fmt::format(
      "CASE 1's launch distribution (Fig. 4.11; text: half-widths ~45 cm/s): s.d. {:.1f} / {:.1f} cm/s and "
      "half width at half maximum {:.1f} / {:.1f} cm/s at u* = {:g} / {:g}.\n\n"
      "CASE 1's hops (text: the half-widths of the hop height, length and impact velocities grow 10-30 % "
      "from u* = 35 to 125), s.d. over the hops:\n\n| quantity | u* = {:g} | u* = {:g} | growth |\n"
      "|---|---|---|---|\n",
      a.sd, b.sd, a.half_width, b.half_width, low.u_star, high.u_star, low.u_star, high.u_star);
  const struct {
    const char* name;
    double at_low, at_high;
  } spreads[] = {{"hop-height", low.r.sd_hop_height, high.r.sd_hop_height},
                 {"hop-length", low.r.sd_hop_length, high.r.sd_hop_length},
                 {"impact-vx", low.r.sd_impact_vx, high.r.sd_impact_vx},
                 {"impact-vy", low.r.sd_impact_vy, high.r.sd_impact_vy}};
  for (const auto& q : spreads) {
    const double growth = q.at_low > 0 ? q.at_high / q.at_low - 1 : 0;
    rep.expect_near(fmt::format("saltation/case-1/spread-growth/{}", q.name), "wind-model", growth, 0.2, 0.1,
                    fmt::format("the s.d. of the {} over the hops grows from u* = {:g} to {:g} by 10-30 % "
                                "(text): {:.3g} -> {:.3g}, {:+.1f} %",
                                q.name, low.u_star, high.u_star, q.at_low, q.at_high, 100 * growth));
    md += fmt::format("| {} | {:.3g} | {:.3g} | {:+.1f} % |\n", q.name, q.at_low, q.at_high, 100 * growth);
  }
  md += "\n";
}

// Eq. 4.35, the thesis's time-dependent model, followed from a seed at CASE 1, u* = 75 cm/s: it must settle
// on the fixed point the steady solver finds (an independent algorithm: physical time, no relaxation).
void transient_section(Report& rep, const Cell& steady, std::string& md) {
  TransientOptions o;
  o.model = steady.options;
  o.dt = 0.01, o.duration = 7;
  const TransientResult t = run_transient(o, kernel_of(table_4_3(1)));
  rep.expect_near(
      "saltation/transient/case-1/u75/mass-flux", "wind-model", t.final_mass_flux, steady.r.mass_flux,
      0.01 * steady.r.mass_flux,
      "eq. 4.35 in time (dt 0.01 s, 7 s from a seed) settles on the steady solver's Q within 1 %");
  rep.expect_near("saltation/transient/case-1/u75/u-star-eff", "wind-model", t.final_u_star_eff,
                  steady.r.u_star_eff, 0.01 * steady.r.u_star_eff, "... and on its u*_eff within 1 %");
  md += fmt::format(
      "Eq. 4.35 in time (CASE 1, u* = 75 cm/s, from a seed of about one launch per cm^2 per s): Q {:.4g} "
      "g/(cm "
      "s) and u*_eff {:.2f} cm/s over the last fifth of 7 s, against the steady solver's {:.4g} and {:.2f}; "
      "the "
      "flux settled within 5 % {:.2f} s after the seed (`grainlab saltation transient`).\n\n",
      t.final_mass_flux, t.final_u_star_eff, steady.r.mass_flux, steady.r.u_star_eff, t.settling_time);
}

// Fig. 4.22: grains of 0.025 and 0.1 cm launched into a sediment-free wind (u* = 160 cm/s, roughness 1 cm).
void fig4_22_section(Report& rep, std::string& md) {
  const std::vector<saltation::CleanWindLaunch> launches = saltation::clean_wind_heights(fig4_22_spec());
  clean_wind_height_checks(rep, launches);
  rep.plots.push_back(clean_wind_height_plot(launches));
  md += "## Fig. 4.22: heights in a sediment-free wind (u* = 160 cm/s, roughness 1 cm)\n\n" +
        clean_wind_height_table(launches) +
        "\nThe small grains' height saturates with launch speed and the large grains rise higher at every "
        "speed, as the thesis found (`grainlab saltation heights`; docs/saltation.md).\n\n";
}

// The first height between one grain diameter and 10 cm where profile `high` crosses profile `low` (both
// on the heights y), interpolated in ln y; 0 if they do not cross there.
double crossing_height(const std::vector<double>& y, const std::vector<double>& low,
                       const std::vector<double>& high) {
  double last = 0;
  bool have = false;
  for (std::size_t k = 0; k < y.size(); ++k) {
    if (y[k] < 0.025 || y[k] > 10) continue;
    const double d = high[k] - low[k];
    if (have && (d > 0) != (last > 0)) {  // crossed between k - 1 and k
      const double t = last / (last - d);
      return std::exp(std::log(y[k - 1]) + t * (std::log(y[k]) - std::log(y[k - 1])));
    }
    last = d, have = true;
  }
  return 0;
}

// The focus: the height where the wind profiles at a case's lowest and highest u* cross (Bagnold's
// measured ~0.2 cm for 0.025 cm sand; the thesis's CASE 1 shows one, CASES 2-4 smear it over ~0.25 cm).
double focus_height(const Cell& low, const Cell& high) {
  return crossing_height(low.r.y, low.r.u, high.r.u);
}

// Where the fluid stress profiles of the same two runs cross. The mixing-length wind grows as
// du / d(ln y) = k sqrt(tau / rho) from u = 0 at l = d/30, so below this height the stronger wind grows
// more slowly, and its profile can only catch up above it: the focus must lie higher than this.
double stress_crossing_height(const Cell& low, const Cell& high) {
  return crossing_height(low.r.y, low.r.tau, high.r.tau);
}

// The focus (Figs 4.13 and 4.17): where the wind profiles of a case's lowest and highest u* cross, and
// how far apart the three pairs' crossings lie. The thesis gives no height for CASE 1's focus (its Fig. 4.13
// is not in the text), so CASE 1 is held to the measurement the thesis sets beside it: Bagnold's profiles
// (Fig. 4.12, via Ungar and Haff 1986), which cross near 0.2 cm for 0.025 cm sand. For the coarse sand of
// CASE 7 the thesis states about 1 cm, and for the splash functions with an exponential term (CASES 2-4
// and 6) a "point" spread over up to about 0.25 cm.
void focus_checks(Report& rep, const std::vector<Cell>& cells, std::string& md) {
  md +=
      "## The focus of the wind profiles\n\nThe wind grows as du / d(ln y) = k sqrt(tau / rho) from the "
      "roughness height d/30, so the profiles can only cross above the height where the fluid stress "
      "profiles cross: the last column.\n\n| CASE | u* | focus height (cm), lowest and highest u* | "
      "the three pairs' crossings (cm) | stress profiles cross (cm) |\n|---|---|---|---|---|\n";
  for (std::size_t i = 0; i + 2 < cells.size(); i += 3) {
    const Cell &a = cells[i], &b = cells[i + 1], &c = cells[i + 2];
    const bool states = a.r.failure.empty() && b.r.failure.empty() && c.r.failure.empty();
    // The focus between the lowest and highest u* with a steady state (CASE 7 has none at 50 cm/s).
    std::vector<const Cell*> steady;
    for (const Cell* x : {&a, &b, &c})
      if (x->r.failure.empty()) steady.push_back(x);
    const double h = steady.size() >= 2 ? focus_height(*steady.front(), *steady.back()) : 0;
    const double hs = steady.size() >= 2 ? stress_crossing_height(*steady.front(), *steady.back()) : 0;
    const std::array<double, 3> pairs{h, states ? focus_height(a, b) : 0, states ? focus_height(b, c) : 0};
    const bool all_cross = states && pairs[0] > 0 && pairs[1] > 0 && pairs[2] > 0;
    const double spread = all_cross ? *std::max_element(pairs.begin(), pairs.end()) -
                                          *std::min_element(pairs.begin(), pairs.end())
                                    : NAN;
    md += fmt::format(
        "| {} | {:g}, {:g}, {:g} | {} | {} | {} |\n", a.case_number, a.u_star, b.u_star, c.u_star,
        steady.size() < 2 ? std::string("fewer than two steady states")
        : h > 0 ? fmt::format("{:.2f} (u* = {:g} and {:g})", h, steady.front()->u_star, steady.back()->u_star)
                : std::string("no crossing"),
        all_cross
            ? fmt::format("{:.2f}, {:.2f}, {:.2f} (spread {:.2f})", pairs[0], pairs[1], pairs[2], spread)
            : std::string("-"),
        hs > 0 ? fmt::format("{:.2f}", hs) : std::string("-"));
    if (a.case_number == 1)
      rep.expect_near(
          "saltation/case-1/focus", "wind-model", h, 0.2, 0.1,
          "CASE 1: the wind profiles at u* = 35 and 125 cm/s cross near Bagnold's measured ~0.2 cm "
          "(Fig. 4.12; the thesis shows its own focus in Fig. 4.13 without a number)");
    if (a.case_number == 7)
      rep.expect_near(
          "saltation/case-7/focus", "wind-model", h, 1.0, 0.25,
          "CASE 7 (coarse sand): the profiles of its lowest and highest u* with a steady state cross "
          "at about 1 cm (thesis, Fig. 4.17, 50-125 cm/s; within 25 %)");
    if ((a.case_number >= 2 && a.case_number <= 4) || a.case_number == 6)
      rep.expect_below(fmt::format("saltation/case-{}/focus-spread", a.case_number), "wind-model",
                       all_cross ? spread : INFINITY, 0.3,
                       "the three pairs of profiles cross within a band of about 0.25 cm (thesis, for the "
                       "splash functions with an exponential term; limit 0.3 cm)");
  }
  md += "\n";
}

void plots(Report& rep, const std::vector<Cell>& cells) {
  PlotSpec eff{
      "saltation_table_4_5.png", "Table 4.5: u*_eff against u*", "u* (cm/s)", "u*_eff (cm/s)", false, {}};
  PlotSpec flux{
      "saltation_flux.png", "Mass flux against u* (dashed: slope 2)", "u* (cm/s)", "Q (g/(cm s))", true, {}};
  flux.logy = true;
  for (std::size_t i = 0; i + 2 < cells.size(); i += 3) {
    PlotSpec::Series ours{fmt::format("CASE {} grainlab", cells[i].case_number), "linepoints", {}, {}, {}};
    PlotSpec::Series thesis{fmt::format("CASE {} thesis", cells[i].case_number), "points", {}, {}, {}};
    PlotSpec::Series q{fmt::format("CASE {}", cells[i].case_number), "linepoints", {}, {}, {}};
    for (std::size_t k = i; k < i + 3; ++k) {
      thesis.x.push_back(cells[k].u_star), thesis.y.push_back(kTable45[cells[k].case_number - 1][k - i]);
      if (!cells[k].r.failure.empty()) continue;  // no steady state to draw
      ours.x.push_back(cells[k].u_star), ours.y.push_back(cells[k].r.u_star_eff);
      q.x.push_back(cells[k].u_star), q.y.push_back(cells[k].r.mass_flux);
    }
    eff.series.push_back(ours), eff.series.push_back(thesis), flux.series.push_back(q);
  }
  const double q0 = std::max(cells.front().r.mass_flux, 1e-300), u0 = cells.front().u_star;
  flux.series.push_back({"Q ~ u*^2", "dashed", {u0, 150}, {q0, q0 * (150 / u0) * (150 / u0)}, {}});
  PlotSpec wind{"saltation_case1_wind.png",
                "CASE 1: wind with grains (dashed: without)",
                "u (cm/s)",
                "y (cm)",
                false,
                {}};
  wind.logy = true;
  for (const Cell& c : cells) {
    if (c.case_number != 1) continue;
    PlotSpec::Series s{fmt::format("u* = {:g}", c.u_star), "line", {}, {}, {}},
        clean{fmt::format("u* = {:g}, no grains", c.u_star), "dashed", {}, {}, {}};
    for (std::size_t k = 0; k < c.r.y.size(); ++k)
      if (c.r.y[k] >= 0.01 && c.r.y[k] <= 30)
        s.x.push_back(c.r.u[k]), s.y.push_back(c.r.y[k]), clean.x.push_back(c.r.u_clean[k]),
            clean.y.push_back(c.r.y[k]);
    wind.series.push_back(s), wind.series.push_back(clean);
  }
  rep.plots.push_back(eff), rep.plots.push_back(flux), rep.plots.push_back(wind);
}

}  // namespace

void run_saltation_suite(Report& rep, const SuiteOptions& o) {
  std::string md = "# Saltation (thesis Ch. IV)\n\n";
  conveyor_checks(rep, md);
  // Quick: the pure rebound splash (CASE 1) and the one with horizontal launches (CASE 5).
  const std::vector<int> cases = o.quick ? std::vector<int>{1, 5} : std::vector<int>{1, 2, 3, 4, 5, 6};
  if (o.log) o.log(fmt::format("wind-driven model: {} cases x 3 u*", cases.size()));
  std::vector<Cell> cells = run_cells(cases, o);
  if (!o.quick) {
    if (o.log) o.log("CASE 7: the sand-gun splash");
    for (Cell& c : run_case7(o)) cells.push_back(std::move(c));
  }
  for (const Cell& c : cells) identity_checks(rep, c);
  table_checks(rep, cells, md);
  case1_text_checks(rep, cells.front(), md);
  if (cells.size() >= 3 && cells[2].case_number == 1 && cells[2].r.converged)
    case1_spread_checks(rep, cells[0], cells[2], md);
  focus_checks(rep, cells, md);
  fig4_22_section(rep, md);
  if (cells.size() >= 2 && cells[1].case_number == 1 && cells[1].u_star == 75 && cells[1].r.failure.empty())
    transient_section(rep, cells[1], md);
  md += o.quick ? "CASE 7 (the sand-gun splash, d = 0.078 cm) runs in the full suite only.\n"
                : "CASE 7 uses the sand-gun splash (Tables 3.11-3.12) for its coarse sand (d = 0.078 cm); a "
                  "rebound slower than sqrt(2 g d) leaves the grain in the bed (docs/saltation.md).\n";
  rep.markdown.push_back(md);
  plots(rep, cells);
}

}  // namespace grainlab::validation
