// Suite `impacts`: the thesis's grain-bed impacts (Ch. III, Tables 3.1-3.9) on grainlab's beds, with
// intervals, beside the thesis's tables; its statements about the impacts as checks; the rebound model
// (Appendix III.1); and the same impacts on the impulse engines that can hold the bed at rest.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "impacts.hpp"
#include "parallel.hpp"
#include "rebound_model.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

// The suite's beds by preparation ("loose", "dense").
using Beds = std::map<std::string, std::vector<Bed>>;

constexpr std::uint64_t kSeed = 2026;

// Case `c`'s `runs` impacts on `beds`, kept in the suite's ensembles folder (if any) as they go, under
// `name`; `what` is logged first, saying so when the impacts of an interrupted run are taken up.
ImpactEnsemble kept_impacts(const SuiteOptions& o, const std::string& name, const std::string& what,
                            const std::vector<Bed>& beds, const ImpactCase& c, std::size_t runs,
                            const ImpactOptions& opt) {
  const std::string checkpoint = o.ensemble_checkpoint(name);
  const bool taken = !checkpoint.empty() && std::filesystem::exists(checkpoint);
  if (o.log) o.log(what + (taken ? ", continuing from the impacts of the interrupted run" : ""));
  return run_impact_ensemble(beds, c, kSeed, runs, opt, o.progress, checkpoint);
}

struct CaseResult {
  ImpactCase c;
  ImpactEnsemble e;
  ImpactSummary s;
};

std::string cell(const MeanInterval& m, int digits = 2) {
  if (m.n == 0 || !std::isfinite(m.mean)) return "-";
  return fmt::format("{:.{}f} ({:.{}f}) [{:.{}f}, {:.{}f}]", m.mean, digits, m.sd, digits, m.lo, digits, m.hi,
                     digits);
}

std::string thesis_cell(const std::map<std::string, std::pair<double, double>>& t, const std::string& k,
                        int digits = 2) {
  const auto it = t.find(k);
  if (it == t.end()) return "-";
  return fmt::format("{:.{}f} ({:.{}f})", it->second.first, digits, it->second.second, digits);
}

// Thesis mean against ours, in units of the combined standard error (thesis spread / sqrt(10), ours
// sd / sqrt(n)).
double z_score(const MeanInterval& m, const std::pair<double, double>& thesis) {
  const double u = std::hypot(thesis.second / std::sqrt(10.0), m.n > 1 ? m.sd / std::sqrt(double(m.n)) : 0.0);
  return u > 0 ? (m.mean - thesis.first) / u : 0.0;
}

// A check that a difference of two means is positive: its 95 % interval (family-corrected z) lies above 0.
void expect_positive_difference(Report& r, const std::string& id, const MeanInterval& a,
                                const MeanInterval& b, double z, const std::string& note) {
  const double se = std::hypot(a.sd / std::sqrt(double(std::max<std::size_t>(a.n, 1))),
                               b.sd / std::sqrt(double(std::max<std::size_t>(b.n, 1))));
  const double diff = a.mean - b.mean, lower = diff - z * se;
  Check c;
  c.id = id, c.engine = "native", c.value = lower, c.reference = 0, c.tolerance = 0;
  c.passed = std::isfinite(lower) && lower > 0;
  c.note = fmt::format("{}: difference {:.3g} +- {:.3g} (z {:.2f}); passes when its lower end is above 0",
                       note, diff, z * se, z);
  r.checks.push_back(c);
}

// Pools the per-impact values of `key` over several cases.
MeanInterval pooled(const std::vector<CaseResult>& results, const std::vector<std::string>& names,
                    const std::string& key, double restitution) {
  std::vector<ImpactResult> all;
  for (const CaseResult& c : results)
    for (const std::string& n : names)
      if (c.c.name == n) all.insert(all.end(), c.e.impacts.begin(), c.e.impacts.end());
  const ImpactSummary s = summarize_impacts(all, restitution);
  return s.q.count(key) ? s.q.at(key) : MeanInterval{};
}

const CaseResult& find(const std::vector<CaseResult>& rs, const std::string& name) {
  for (const CaseResult& c : rs)
    if (c.c.name == name) return c;
  throw std::logic_error("impacts suite: no case " + name);
}

std::string bed_section(const Beds& beds) {
  std::string md =
      "### The beds\n\n384 discs (r_b = 1 cm, 2 g/cm^2, k_n = k_s = 6e9 dyn/cm, restitution 0.85, mu 0.5) in "
      "the "
      "open-topped 67.3 x 24.1 cm box. Loose: rained in with friction; dense: rained in frictionless, "
      "friction "
      "restored at rest; both levelled (poured with 15 % extra discs, the highest scraped off) and stiffened "
      "from a 100 x softer pour in ten critically damped steps (docs/impacts.md).\n\n"
      "| preparation | seed | packing fraction | coordination | top (cm) | roughness (cm) | brinks | "
      "anti-brinks "
      "| build (s) |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [prep, list] : beds)
    for (const Bed& b : list)
      md += fmt::format("| {} | {} | {:.4f} | {:.2f} | {:.2f} | {:.3f} | {} | {} | {:.1f} |\n", prep,
                        b.spec.seed, b.stats.packing_fraction, b.stats.coordination, b.stats.top,
                        b.stats.roughness, b.stats.brinks, b.stats.anti_brinks, b.stats.build_seconds);
  return md + "\n";
}

// One markdown table of `keys`, thesis beside grainlab, with the z-score of each thesis mean.
std::string comparison_table(const std::string& title, const std::vector<CaseResult>& rs,
                             const std::vector<std::pair<std::string, std::string>>& keys, int digits,
                             std::vector<std::string>& off) {
  std::string md = "### " + title +
                   "\n\nEach cell: thesis mean (half-width) | grainlab mean (sd) [95 % interval] | "
                   "z = (grainlab - thesis) / combined standard error.\n\n| CASE |";
  for (const auto& k : keys) md += " " + k.second + " thesis | grainlab | z |";
  md += "\n|---|";
  for (std::size_t k = 0; k < keys.size(); ++k) md += "---|---|---|";
  md += "\n";
  for (const CaseResult& c : rs) {
    const auto t = thesis_impact_values(c.c.name);
    md += "| " + c.c.name + " |";
    for (const auto& [key, label] : keys) {
      const MeanInterval m = c.s.q.count(key) ? c.s.q.at(key) : MeanInterval{};
      std::string z = "-";
      if (t.count(key) && m.n > 0 && std::isfinite(m.mean)) {
        const double zz = z_score(m, t.at(key));
        z = fmt::format("{:+.1f}", zz);
        if (std::abs(zz) > 1.96) off.push_back(fmt::format("{} {} ({})", c.c.name, label, z));
      }
      md += fmt::format(" {} | {} | {} |", thesis_cell(t, key, digits), cell(m, digits), z);
    }
    md += "\n";
  }
  return md + "\n";
}

void rebound_model_checks(Report& r) {
  // Mean contact angle on a touching bed and CASE 2's vertical amplification (spec section 4): pure
  // geometry and eq. 3.A.1, computed here by quadrature over 20,000 impact points.
  const double beta15 = rebound_model(rebound_case(2, 15)).beta_deg,
               beta25 = rebound_model(rebound_case(2, 25)).beta_deg;
  r.expect_near("impacts/rebound-model/beta-15", "model", beta15, 12.9, 0.05,
                "mean beta at alpha 15 deg on a touching bed (thesis 12.9, printed to one decimal; spec's "
                "derived 12.86)");
  r.expect_near("impacts/rebound-model/beta-25", "model", beta25, 10.9, 0.05,
                "mean beta at alpha 25 deg on a touching bed (thesis 10.9, printed to one decimal; spec's "
                "derived 10.93, not reproduced to its second decimal)");
  const double want[3] = {1.01, 0.63, 0.21}, alpha[3] = {15, 25, 70};
  for (int k = 0; k < 3; ++k)
    r.expect_near(fmt::format("impacts/rebound-model/case2-eps-iy-{}", alpha[k]), "model",
                  rebound_model(rebound_case(2, alpha[k])).eps_iy, want[k], 0.005,
                  fmt::format("CASE 2 mean eps_iy at {} deg (printed to two decimals)", alpha[k]));
  // Table 3.3's m_beff from Table 3.2's means, through the two-body law with the mean beta.
  struct Row {
    const char* c;
    double a, b, eix, eiy, m, tol;
  };
  const Row rows[] = {{"A", 15, 17, .59, 1.12, 1.9, .05},
                      {"B", 25, 16, .53, .68, 1.9, .05},
                      {"D", 15, 17, .85, 1.07, 1.3, .05},
                      {"C", 70, -4, .54, .25, 2.3, .15},
                      {"E", 15, 13, .60, 1.06, 2.2, .15}};
  for (const Row& w : rows)
    r.expect_near(fmt::format("impacts/two-body-m-beff/{}", w.c), "model",
                  effective_mass_two_body(w.a, w.b, w.eix, w.eiy, 0.85), w.m, w.tol,
                  fmt::format("CASE {}: Table 3.2 means through eq. 3.A.1 give Table 3.3's m_beff/m_b "
                              "(tolerance: the printed rounding{})",
                              w.c, w.tol > 0.1 ? ", and beta's spread for C and E" : ""));
}

void statement_checks(Report& r, const std::vector<CaseResult>& rs, double eps) {
  const double z = family_z(6);
  const auto q = [&](const char* c, const char* k) { return find(rs, c).s.q.at(k); };
  std::vector<double> masses;
  for (const char* n : {"A", "B", "C", "E", "F", "G"}) masses.push_back(q(n, "m_beff").mean);
  const MeanInterval frictional = mean_interval(masses);
  r.expect_near(
      "impacts/m-beff-frictional", "native", frictional.mean, 2.0, 0.4,
      fmt::format("m_beff / m_b averaged over the frictional cases A-C, E-G (thesis: close to 2 with a "
                  "10-20 % spread; tolerance 20 %); the cases: {:.2f}",
                  fmt::join(masses, ", ")));
  {
    // The thesis's frictional and frictionless beds had the same surface (beta 17 +- 5). grainlab's dense bed
    // matches that (beta 18); its loose bed is rougher (beta 26), and there the effect of friction on m_beff
    // drowns (reported, docs/impacts.md). G and D-dense share beds and impact points: a paired comparison.
    const MeanInterval d =
        effective_mass_difference(find(rs, "G").e.impacts, find(rs, "D-dense").e.impacts, eps);
    Check c;
    c.id = "impacts/m-beff-frictionless-lighter", c.engine = "native", c.value = d.lo;
    c.passed = std::isfinite(d.lo) && d.lo > 0;
    c.note = fmt::format(
        "m_beff(G) - m_beff(D on the dense bed), paired over the same impact points: {:.3f} [{:.3f}, {:.3f}] "
        "(thesis 1.9 - 1.3 = 0.6); passes when the interval's lower end is above 0",
        d.mean, d.lo, d.hi);
    r.checks.push_back(c);
  }
  expect_positive_difference(r, "impacts/eps-iy-falls-15-25", q("A", "eps_iy"), q("B", "eps_iy"), z,
                             "eps_iy(A, 15 deg) - eps_iy(B, 25 deg)");
  expect_positive_difference(r, "impacts/eps-iy-falls-25-70", q("B", "eps_iy"), q("C", "eps_iy"), z,
                             "eps_iy(B, 25 deg) - eps_iy(C, 70 deg)");
  expect_positive_difference(r, "impacts/low-energy-ejects-fewer", q("A", "ejected"), q("E", "ejected"), z,
                             "ejecta per impact, A (3000 cm/s) - E (1000 cm/s)");
  const MeanInterval angle = pooled(rs, {"A", "B", "C", "D", "E", "F"}, "ej_angle", eps);
  Check c;
  c.id = "impacts/ejecta-angles-small-positive", c.engine = "native", c.value = angle.mean;
  c.reference = 15, c.tolerance = 15;
  c.passed = angle.lo > 0 && angle.hi < 30;
  c.note = fmt::format(
      "mean ejection angle from the vertical on the loose bed, cases A-F pooled: {:.1f} deg, 95 % "
      "interval [{:.1f}, {:.1f}]; passes inside (0, 30) deg",
      angle.mean, angle.lo, angle.hi);
  r.checks.push_back(c);
  std::vector<ImpactResult> ac;
  for (const char* n : {"A", "B", "C", "D", "E", "F"})
    ac.insert(ac.end(), find(rs, n).e.impacts.begin(), find(rs, n).e.impacts.end());
  const ImpactSummary s = summarize_impacts(ac, eps);
  expect_positive_difference(
      r, "impacts/brinks-eject-at-larger-angles", s.q.at("ej_angle_brink"), s.q.at("ej_angle_other"), z,
      "ejection angle of brink grains - of other grains, loose cases A-F pooled (thesis, "
      "A-C: 44-50 vs 1-5 deg)");
}

std::vector<PlotSpec> impact_plots(const std::vector<CaseResult>& rs) {
  std::vector<PlotSpec> plots;
  PlotSpec rebound{"impacts_rebound.png",
                   "Rebound velocity of the incident grain (native)",
                   "v_x out / v_i",
                   "v_y out / v_i",
                   false,
                   {}};
  PlotSpec ejecta{"impacts_ejecta.png",
                  "Ejecta velocities at one diameter above the bed (native)",
                  "v_x (cm/s)",
                  "v_y (cm/s)",
                  false,
                  {}};
  PlotSpec mass{"impacts_m_beff.png",
                "Effective target mass per case (two-body inversion)",
                "case (A..I = 1..9; D on the dense bed = 10)",
                "m_beff / m_b",
                false,
                {}};
  PlotSpec::Series ours{"grainlab (95 % interval)", "points", {}, {}, {}},
      thesis{"thesis (half-width)", "points", {}, {}, {}};
  for (std::size_t k = 0; k < rs.size(); ++k) {
    const CaseResult& c = rs[k];
    PlotSpec::Series rb{"CASE " + c.c.name, "points", {}, {}, {}},
        ej{"CASE " + c.c.name, "points", {}, {}, {}};
    for (const ImpactResult& r : c.e.impacts) {
      if (r.rebounded) rb.x.push_back(r.vx / r.incident_speed), rb.y.push_back(r.vy / r.incident_speed);
      for (const Ejectum& e : r.ejecta) ej.x.push_back(e.vx), ej.y.push_back(e.vy);
    }
    rebound.series.push_back(rb);
    ejecta.series.push_back(ej);
    const MeanInterval m = c.s.q.at("m_beff");
    ours.x.push_back(double(k + 1)), ours.y.push_back(m.mean), ours.err.push_back(m.half_width());
    const auto t = thesis_impact_values(c.c.name);
    if (t.count("m_beff"))
      thesis.x.push_back(double(k + 1) + 0.15), thesis.y.push_back(t.at("m_beff").first),
          thesis.err.push_back(t.at("m_beff").second);
  }
  mass.series = {ours, thesis};
  plots.push_back(rebound);
  plots.push_back(ejecta);
  plots.push_back(mass);
  return plots;
}

void add_samples(Report& r, const std::string& prefix, const CaseResult& c, double eps) {
  SampleTable t{prefix + "/" + c.c.name,
                fmt::format("CASE {}: one row per impact (cgs, degrees)", c.c.name),
                {"run", "rebounded", "eps_ix", "eps_iy", "theta_i", "xi_i", "beta", "m_beff", "ejected",
                 "reptation", "x_impact", "vx_out", "vy_out", "spin_out"},
                {}};
  SampleTable ej{prefix + "/" + c.c.name + "_ejecta",
                 "every ejectum: velocity at one diameter above the top, launch "
                 "velocity, origin relative to the impact point, type (0 other, 1 "
                 "target, 2 brink, 3 anti-brink)",
                 {"run", "vx", "vy", "vx_launch", "vy_launch", "x0", "y0", "type", "time"},
                 {}};
  for (std::size_t i = 0; i < c.e.impacts.size(); ++i) {
    const ImpactResult& r0 = c.e.impacts[i];
    const ImpactMeasures m = measure_impact(r0, eps);
    t.rows.push_back({double(i), m.rebounded, m.eps_ix, m.eps_iy, m.theta_i, m.xi_i, m.beta, m.m_beff,
                      m.ejected, m.reptation, r0.x_impact, r0.vx, r0.vy, r0.spin});
    for (const Ejectum& e : r0.ejecta)
      ej.rows.push_back({double(i), e.vx, e.vy, e.vx_launch, e.vy_launch, e.x0, e.y0,
                         double(static_cast<int>(e.type)), e.time});
  }
  r.samples.push_back(t);
  r.samples.push_back(ej);
}

// Box2D, ODE and Bullet on the same beds: first whether each holds the bed at rest, then CASE A (loose)
// and G (dense) beside native.
std::string cross_engine_section(Report& rep, const Beds& beds, const std::vector<CaseResult>& native,
                                 const SuiteOptions& o, std::size_t runs) {
  std::string md =
      "### The impulse engines on the same beds\n\n"
      "Each engine first holds each bed alone for 0.07 s; one that lets a disc move more than 0.05 cm "
      "or leaves one faster than 1 cm/s is excluded with a capability error (its \"ejecta\" would be "
      "the bed settling). Impulse engines step at 1e-5 s.\n\n"
      "| engine | bed | largest displacement (cm) | largest speed (cm/s) | held |\n|---|---|---|---|---|\n";
  ImpactOptions opt;
  std::string rows;
  for (const std::string engine : {"box2d", "ode", "bullet"}) {
    for (const std::string prep : {"loose", "dense"}) {
      const BedHold h = hold_bed(beds.at(prep)[0], engine, opt.duration, opt.rigid_dt);
      bool held = true;
      std::string why;
      try {
        check_bed_held(h, engine);
      } catch (const std::exception& e) {
        held = false, why = e.what();
      }
      md += fmt::format("| {} | {} | {:.3g} | {:.3g} | {} |\n", engine, prep, h.max_displacement, h.max_speed,
                        held ? "yes" : "no");
      Check& c = rep.expect_below(fmt::format("impacts/holds-bed/{}/{}", engine, prep), engine,
                                  h.max_displacement, 0.05,
                                  fmt::format("{} bed alone for 0.07 s: largest displacement (cm); largest "
                                              "speed {:.3g} cm/s (limit 1)",
                                              prep, h.max_speed));
      c.passed = held;
      if (!held) {
        c.known_limitation("cannot hold the Ch. III bed at rest: " + why);
        continue;
      }
      if (o.quick && prep == "dense") continue;  // quick: CASE A only
      const ImpactCase& ic = impact_case(prep == "loose" ? "A" : "G");
      opt.engine = engine;
      const ImpactEnsemble e =
          kept_impacts(o, fmt::format("impacts-case-{}-{}", ic.name, engine),
                       fmt::format("impacts: CASE {} on {} ({} impacts)", ic.name, engine, runs),
                       beds.at(prep), ic, runs, opt);
      const ImpactSummary s = summarize_impacts(e.impacts, 0.85);
      const ImpactSummary& n = find(native, ic.name).s;
      for (const char* k : {"m_beff", "eps_iy", "eps_ix", "ejected", "ej_speed"})
        rows +=
            fmt::format("| {} | {} | {} | {} | {} |\n", ic.name, engine, k, cell(s.q.at(k)), cell(n.q.at(k)));
      rows += fmt::format("| {} | {} | seconds per impact | {:.2f} | {:.2f} |\n", ic.name, engine,
                          s.median_wall_seconds, n.median_wall_seconds);
    }
  }
  if (!rows.empty())
    md +=
        "\n| CASE | engine | quantity | engine: mean (sd) [95 %] | native |\n|---|---|---|---|---|\n" + rows;
  return md + "\n";
}

// `n` beds of each preparation, seeds 1..n.
Beds build_beds(const SuiteOptions& o, std::size_t n) {
  Beds beds;
  for (const std::string prep : {"loose", "dense"})
    for (std::size_t k = 0; k < n; ++k) {
      BedSpec spec;
      spec.preparation = prep, spec.seed = k + 1;
      if (o.log) o.log(fmt::format("impacts: building {} bed {} of {}", prep, k + 1, n));
      beds[prep].push_back(build_bed(spec));
    }
  return beds;
}

// Every case of Table 3.1 on the native engine (one impact of each recorded to the output folder), and
// CASE D's frictionless grains on the dense bed too: the dense bed's contact angles match the thesis's
// (its loose bed was as smooth), so friction's effect on m_beff is compared there as well.
std::vector<CaseResult> native_cases(const SuiteOptions& o, Beds& beds, std::size_t runs, double eps) {
  const std::size_t n_beds = beds["loose"].size();
  std::vector<CaseResult> results;
  const ImpactOptions opt;
  for (const ImpactCase& c : impact_cases()) {
    CaseResult cr{c,
                  kept_impacts(o, "impacts-case-" + c.name,
                               fmt::format("impacts: CASE {} ({} impacts on {} {} bed(s))", c.name, runs,
                                           n_beds, c.bed),
                               beds[c.bed], c, runs, opt),
                  {}};
    cr.s = summarize_impacts(cr.e.impacts, eps);
    results.push_back(std::move(cr));
    if (!o.out_dir.empty() && parallel::rank() == 0) {
      ImpactOptions rec = opt;
      rec.record = o.out_dir + "/impact_" + c.name + ".h5", rec.overwrite = true;
      run_impact(beds[c.bed][0], c, kSeed, 0, rec);
    }
  }
  const ImpactCase dd{"D-dense", 3000, 15, 0.0, "dense", 1.0};
  CaseResult cr{dd,
                kept_impacts(o, "impacts-case-D-dense",
                             fmt::format("impacts: CASE D on the dense beds ({} impacts)", runs),
                             beds["dense"], dd, runs, opt),
                {}};
  cr.s = summarize_impacts(cr.e.impacts, eps);
  results.push_back(std::move(cr));
  return results;
}

// Friction's share of the effective mass, paired over the same impact points on both preparations.
std::string friction_paragraph(const std::vector<CaseResult>& results, double eps) {
  const MeanInterval loose =
      effective_mass_difference(find(results, "A").e.impacts, find(results, "D").e.impacts, eps);
  const MeanInterval dense =
      effective_mass_difference(find(results, "G").e.impacts, find(results, "D-dense").e.impacts, eps);
  return fmt::format(
      "**Friction and the effective mass.** Paired over the same impact points, friction raises m_beff / "
      "m_b by "
      "{:.2f} [{:.2f}, {:.2f}] on the loose beds (A - D, mean beta {:.0f} deg) and by {:.2f} [{:.2f}, "
      "{:.2f}] on "
      "the dense beds (G - D-dense, mean beta {:.0f} deg); the thesis: 0.6 on a bed with beta 17 deg.\n\n",
      loose.mean, loose.lo, loose.hi, find(results, "A").s.q.at("beta").mean, dense.mean, dense.lo, dense.hi,
      find(results, "G").s.q.at("beta").mean);
}

// Tables 3.2-3.9 beside grainlab's numbers; `off` collects the thesis means outside grainlab's intervals.
std::string thesis_tables(const std::vector<CaseResult>& results, std::vector<std::string>& off) {
  std::string md = comparison_table("Table 3.2: the rebounding grain", results,
                                    {{"eps_ix", "eps_ix"},
                                     {"eps_iy", "eps_iy"},
                                     {"eps_i", "eps_i"},
                                     {"theta_i", "theta_i"},
                                     {"xi_i", "xi_i"},
                                     {"beta", "beta"}},
                                    2, off);
  md += comparison_table(
      "Table 3.3: momentum to the bed", results,
      {{"eps_bx", "eps_bx"}, {"eps_by", "eps_by"}, {"theta_b", "Theta_b"}, {"m_beff", "m_beff/m_b"}}, 2, off);
  md += comparison_table("Table 3.4: ejecta (cm/s, degrees from vertical, cm)", results,
                         {{"ej_speed", "speed"},
                          {"ej_vy", "v_y"},
                          {"ej_angle", "angle"},
                          {"reptation", "reptation"},
                          {"ejected", "number"}},
                         1, off);
  md += comparison_table(
      "Table 3.5: ejected momentum per event (g cm/s) and Table 3.6: ejected energy / incident "
      "(grainlab only; the thesis's table is lost in the OCR)",
      results, {{"ej_px", "x"}, {"ej_py", "y"}, {"ej_energy", "energy"}}, 0, off);
  const std::vector<CaseResult> abc(results.begin(), results.begin() + 3);
  md += comparison_table(
      "Tables 3.7 and 3.8: by particle type (brink: the two grains just upstream of a drop of at "
      "least r_b between consecutive surface grains)",
      abc,
      {{"ej_angle_target", "target angle"},
       {"ej_angle_brink", "brink angle"},
       {"ej_angle_other", "other angle"},
       {"ej_pex_target", "target p_ex"},
       {"ej_pex_brink", "brink p_ex"},
       {"ej_pex_other", "other p_ex"},
       {"reptation_brink", "brink reptation"}},
      2, off);
  md += comparison_table("Table 3.9: origin of ejecta relative to the impact point (cm)", results,
                         {{"origin_x", "x"}, {"origin_y", "y"}, {"origin_r", "distance"}}, 1, off);
  return md;
}

// The thesis's statements are statistical: with the quick suite's 8 impacts per case they are measured
// and shown but not checked (too few impacts to decide them either way); the full suite checks them.
std::string statements_section(Report& r, const std::vector<CaseResult>& results, double eps, bool quick) {
  Report statements;
  statement_checks(statements, results, eps);
  if (!quick) {
    for (const Check& c : statements.checks) r.checks.push_back(c);
    return "";
  }
  std::string md =
      "### The thesis's statements (measured; checked only by the full suite, 100 impacts per case)\n\n"
      "| statement | value | note |\n|---|---|---|\n";
  for (const Check& c : statements.checks) md += fmt::format("| {} | {:.4g} | {} |\n", c.id, c.value, c.note);
  return md + "\n";
}

}  // namespace

void run_impacts_suite(Report& r, const SuiteOptions& o) {
  const std::size_t runs = o.quick ? 8 : 100, n_beds = o.quick ? 1 : 3;
  Beds beds = build_beds(o, n_beds);
  const double eps = beds["loose"][0].spec.restitution;
  const std::vector<CaseResult> results = native_cases(o, beds, runs, eps);
  std::string md = "## Grain-bed impacts (thesis Ch. III)\n\n" + bed_section(beds);
  md += friction_paragraph(results, eps);
  md += fmt::format(
      "{} impacts per case on {} bed(s) per preparation, seed {}, native engine (Verlet at 1/30 of the "
      "shortest contact). Median cost per impact: ",
      runs, n_beds, kSeed);
  for (const CaseResult& c : results) md += fmt::format("{} {:.2f} s, ", c.c.name, c.s.median_wall_seconds);
  md += "on one core.\n\n";
  std::vector<std::string> off;
  md += thesis_tables(results, off);
  md += fmt::format(
      "Thesis means more than 1.96 combined standard errors from grainlab's: {} of the compared "
      "quantities: {}.\n\n",
      off.size(), fmt::join(off, "; "));
  md += statements_section(r, results, eps, o.quick);
  rebound_model_checks(r);
  md += cross_engine_section(r, beds, results, o, o.quick ? 2 : 30);
  r.markdown.push_back(md);
  for (const PlotSpec& p : impact_plots(results)) r.plots.push_back(p);
  for (const CaseResult& c : results) add_samples(r, "impacts/native", c, eps);
}

}  // namespace grainlab::validation
