// The sand-gun experiment with spheres: the tables' rows, the sand bed, and Tables 3.11-3.12's quantities.
#include "sand_gun3d.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "binary_fingerprint.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
#include "splash_file.hpp"

namespace grainlab::validation {

namespace {
constexpr double kDeg = M_PI / 180;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kSandRadius = 0.039, kSieveHalfWidth = 0.0035;  // 0.071-0.085 cm
}  // namespace

const std::vector<SandGunRow>& sand_gun_rows() {
  // The tables live once, as the measured splash file the saltation and ripple models read; here they are
  // put back into cm and cm/s.
  static const std::vector<SandGunRow> rows = [] {
    const saltation::SplashFile f = saltation::sand_gun_splash();
    const double u = f.velocity_scale(), d = f.grain_diameter_cm;
    std::vector<SandGunRow> out;
    for (const saltation::SplashCell& c : f.cells) {
      SandGunRow r;
      r.index = out.size() + 1;
      r.speed = c.speed * u, r.alpha_deg = c.angle_deg, r.events = c.impacts;
      for (const char* k : {"eps_ix", "eps_iy", "theta_i"}) {
        r.measured[k] = c.moments.at(k).mean;
        r.measured_sd[k] = c.moments.at(k).sd;
      }
      r.measured["energy_ratio"] = c.moments.at("energy_ratio").mean;
      r.measured["ejecta"] = c.moments.at("ejecta_per_impact").mean;
      r.measured["reptation"] = c.moments.at("reptation_per_ejectum").mean * d;
      r.measured["reptation_event"] = r.measured["ejecta"] * r.measured["reptation"];
      r.measured["ej_vz"] = c.moments.at("ejecta_vy").mean * u;
      r.measured["theta_e"] = c.moments.at("ejecta_angle").mean;
      out.push_back(r);
    }
    return out;
  }();
  return rows;
}

Bed3dSpec sand_gun_bed_spec(int count, double stiffness_factor) {
  Bed3dSpec s;
  s.count = count;
  s.radius = kSandRadius, s.radius_spread = kSieveHalfWidth;
  s.density = 2.65;
  s.k_n = 2e7 * stiffness_factor;
  s.restitution = 0.85, s.mu = 0.5;
  // 20,000 spheres in 5.0 x 2.5 cm stand about 10 diameters deep (5,000 in a quarter of the area: 0.76 cm);
  // smaller beds keep the 2:1 footprint and the depth.
  const double area = 12.5 * count / 20000.0;
  s.width = std::sqrt(2 * area), s.depth = s.width / 2;
  s.time_scale = std::sqrt(kSandRadius / 1.0);
  s.settle_time = 1.0;
  return s;
}

ImpactCase sand_gun_case(const SandGunRow& row) {
  ImpactCase c;
  c.name = fmt::format("sand-gun {}", row.index);
  c.speed = row.speed, c.alpha_deg = row.alpha_deg, c.mu = 0.5;
  c.radius = kSandRadius;
  return c;
}

ImpactOptions sand_gun_options(const Bed3dSpec& bed) {
  ImpactOptions o;
  o.duration *= bed.time_scale;
  o.check_interval *= bed.time_scale;
  return o;
}

std::map<std::string, MeanInterval> sand_gun_quantities(const std::vector<Impact3dResult>& impacts) {
  return sand_gun_quantities(impacts, 1, 1);  // 1 d above the top: the diameter does not enter
}

std::map<std::string, MeanInterval> sand_gun_quantities(const std::vector<Impact3dResult>& impacts,
                                                        double visible_above, double diameter) {
  if (!(diameter > 0) || !(visible_above >= 1))
    throw std::invalid_argument("sand_gun_quantities: visible_above must be >= 1 and the diameter > 0 cm");
  // An ejectum is recorded as its centre crosses top + 1 d moving up at e.vz; its apex is e.vz^2 / 2g
  // higher.
  const double extra_rise = std::max(0.0, visible_above - 1) * diameter;
  std::map<std::string, std::vector<double>> v;
  for (const Impact3dResult& r : impacts) {
    const double a = r.alpha_deg * kDeg, speed = r.incident_speed;
    const double vx_in = speed * std::cos(a), vz_in = speed * std::sin(a);
    auto rebound = [&](double x) { return r.rebounded ? x : kNaN; };
    v["eps_ix"].push_back(rebound(r.vx / vx_in));
    v["eps_iy"].push_back(rebound(r.vz / vz_in));
    // The photographs see the incident plane: the rebound angle and energy of the projection.
    v["theta_i"].push_back(rebound(std::atan2(r.vx, r.vz) / kDeg));
    v["energy_ratio"].push_back(rebound((r.vx * r.vx + r.vz * r.vz) / (speed * speed)));
    v["eps_lateral"].push_back(rebound(r.vy / speed));
    double reptation = 0;
    std::size_t counted = 0;
    for (const Ejectum3d& e : r.ejecta) {
      if (e.vz * e.vz / (2 * r.g) < extra_rise) continue;
      ++counted;
      const double range = 2 * e.vx * e.vz / r.g;
      reptation += range;
      v["reptation"].push_back(range);
      v["ej_vz"].push_back(e.vz);
      v["theta_e"].push_back(std::atan2(e.vx, e.vz) / kDeg);
      v["ej_sideways"].push_back(std::abs(std::sin(std::atan2(e.vy, e.vx))));
    }
    v["ejecta"].push_back(static_cast<double>(counted));
    v["reptation_event"].push_back(reptation);
  }
  std::map<std::string, MeanInterval> q;
  for (const auto& [k, x] : v) q[k] = mean_interval(x);
  return q;
}

namespace {
// Least squares of log y on log x with weights w: the slope and its standard error (from the weights when
// `weighted`, from the residuals otherwise).
PowerLaw log_fit(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& w,
                 bool weighted) {
  double sw = 0, sx = 0, sy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    sw += w[i], sx += w[i] * std::log(x[i]), sy += w[i] * std::log(y[i]);
  const double mx = sx / sw, my = sy / sw;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double dx = std::log(x[i]) - mx;
    sxx += w[i] * dx * dx, sxy += w[i] * dx * (std::log(y[i]) - my);
  }
  if (x.size() < 2 || sxx <= 0) return {kNaN, kNaN};
  return {sxy / sxx, weighted ? 1.959963984540054 / std::sqrt(sxx) : 0.0};
}
}  // namespace

PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<MeanInterval>& y) {
  std::vector<double> xs, ys, w;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!(y[i].mean > 0) || y[i].n < 2) continue;
    // The standard error of log(mean) is se / mean; a row with no spread gets the smallest error seen.
    const double se = y[i].half_width() / t_975(y[i].n - 1) / y[i].mean;
    xs.push_back(x[i]), ys.push_back(y[i].mean), w.push_back(se > 0 ? 1 / (se * se) : 0);
  }
  double most = 0;
  for (double wi : w) most = std::max(most, wi);
  for (double& wi : w)
    if (wi == 0) wi = most > 0 ? most : 1;
  return log_fit(xs, ys, w, true);
}

PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<double>& y) {
  return log_fit(x, y, std::vector<double>(x.size(), 1.0), false);
}

std::vector<Impact3dResult> checkpointed_impacts(SandGunProgress& kept, std::size_t row, const Bed3d& bed,
                                                 const ImpactCase& c, std::size_t runs, std::uint64_t seed,
                                                 const ImpactOptions& o, const std::string& checkpoint,
                                                 const EnsembleProgress& progress,
                                                 const std::string& impacts_of) {
  std::vector<std::size_t> missing;
  for (std::size_t i = 0; i < runs; ++i)
    if (!kept.done.count({row, i})) missing.push_back(i);
  const std::size_t round = static_cast<std::size_t>(parallel::size());
  // (Told before the first impact too: the time-left estimate counts from what was done when it began,
  // and told first only after an impact it said "left 0m00s" until the second.)
  if (progress && !missing.empty()) progress(runs - missing.size(), runs);
  for (std::size_t k = 0; k < missing.size(); k += round) {
    const std::vector<std::size_t> these(
        missing.begin() + static_cast<long>(k),
        missing.begin() + static_cast<long>(std::min(k + round, missing.size())));
    const std::vector<Impact3dResult> r = run_impact3d_indices(bed, c, seed, these, o);
    for (std::size_t j = 0; j < these.size(); ++j) kept.done[{row, these[j]}] = r[j];
    if (parallel::rank() == 0) write_sand_gun_checkpoint(checkpoint, kept, seed, impacts_of);
    if (progress) progress(runs - missing.size() + k + these.size(), runs);
  }
  std::vector<Impact3dResult> out;
  for (std::size_t i = 0; i < runs; ++i) out.push_back(kept.done.at({row, i}));
  return out;
}

namespace {

// FNV-1a over the bed's spheres (positions, orientations and radii, as stored): two beds with the same
// spec but other spheres (a build by another binary, a bed settled on an impulse engine) differ here.
std::string bed_fingerprint(const Bed3d& bed) {
  std::uint64_t h = kFnvOffsetBasis;
  for (const Body3Spec& g : bed.scene.bodies3d) {
    const double v[] = {g.position.x(),    g.position.y(),    g.position.z(),    g.orientation.w(),
                        g.orientation.x(), g.orientation.y(), g.orientation.z(), g.radius};
    h = fnv1a(v, sizeof v, h);
  }
  return fmt::format("{:016x} ({} grains)", h, bed.scene.bodies3d.size());
}

}  // namespace

std::vector<Impact3dResult> kept_case_impacts(const std::string& checkpoint, const Bed3d& bed,
                                              const ImpactCase& c, std::size_t runs, std::uint64_t seed,
                                              const ImpactOptions& o, const EnsembleProgress& progress) {
  if (checkpoint.empty()) return run_impact3d_ensemble(bed, c, seed, runs, o, progress);
  std::string impacts_of = fmt::format(
      "suite case {} speed {:.17g} alpha {:.17g} mu {:.17g} radius {:.17g} engine {} steps_per_contact "
      "{:.17g} duration {:.17g} window {:.17g} rigid_dt {:.17g} bed {}",
      c.name, c.speed, c.alpha_deg, c.mu, c.radius, o.engine, o.steps_per_contact, o.duration, o.window,
      o.rigid_dt, bed_fingerprint(bed));
  if (o.active_radius > 0) impacts_of += " " + sand_gun_impacts_of(o.active_radius / (2 * bed.spec.radius));
  SandGunProgress kept;
  try {
    if (auto p = read_sand_gun_checkpoint(checkpoint, bed.spec, seed, impacts_of)) kept = std::move(*p);
  } catch (const InputError& e) {
    throw InputError({}, "--sand-gun-checkpoint",
                     fmt::format("{}: {} (delete it to run CASE {} on {} afresh)", checkpoint, e.message(),
                                 c.name, o.engine));
  }
  kept.bed = bed;
  kept.build = build_record(bed);
  kept.build.finished = true;
  return checkpointed_impacts(kept, 1, bed, c, runs, seed, o, checkpoint, progress, impacts_of);
}

namespace {

// How far the checkpoint's stage under way had gone, for the log.
std::string stage_under_way(const Bed3dBuild& b) {
  if (b.runs_done.rows.empty() && b.run_under_way.empty()) return "";
  const std::size_t runs =
      b.runs_done.rows.empty() ? 0 : static_cast<std::size_t>(b.runs_done.rows.back()[0]) + 1;
  double t = 0;
  if (const auto it = b.run_under_way.find(std::string(kStageWorld) + "clock");
      it != b.run_under_way.end() && !it->second.rows.empty() && !it->second.rows[0].empty())
    t = it->second.rows[0][0];
  return b.run_under_way.empty()
             ? fmt::format("; of the next, {} finished runs", runs)
             : fmt::format("; of the next, {} finished runs and {:.4f} s of the run under way", runs, t);
}

}  // namespace

void finish_checkpointed_bed(SandGunProgress& kept, const Bed3dSpec& spec, std::uint64_t seed,
                             const std::function<void(const std::string&)>& log,
                             const std::string& checkpoint, const std::string& impacts_of) {
  if (kept.build.finished) return;
  kept.bed.spec = spec;
  auto keep_stage = [&](const Bed3dBuild& b) {
    if (checkpoint.empty() || parallel::rank() != 0) return;
    kept.build = b;
    write_sand_gun_checkpoint(checkpoint, kept, seed, impacts_of);
  };
  kept.bed = build_bed3d(spec, log, std::move(kept.build), keep_stage);
  kept.build = Bed3dBuild{};  // the bed holds it now (the last stage's checkpoint has it as finished)
  kept.build.finished = true;
}

SandGunRun run_sand_gun(const Bed3dSpec& spec, const std::vector<std::size_t>& rows, std::size_t runs,
                        std::uint64_t seed, const std::function<void(const std::string&)>& log,
                        const EnsembleProgress& progress, const std::string& checkpoint, double active_zone) {
  if (!(active_zone >= 0)) throw std::invalid_argument("sand gun: the active zone must be >= 0 diameters");
  const std::string impacts_of = sand_gun_impacts_of(active_zone);
  SandGunRun out;
  out.active_zone = active_zone;
  for (std::size_t i : rows) {
    if (i < 1 || i > sand_gun_rows().size())
      throw std::invalid_argument(fmt::format("sand-gun row {} (the tables have rows 1-9)", i));
    out.rows.push_back(sand_gun_rows()[i - 1]);
  }
  if (rows.empty()) out.rows = sand_gun_rows();
  SandGunProgress kept;
  if (std::optional<SandGunProgress> p =
          checkpoint.empty() ? std::nullopt : read_sand_gun_checkpoint(checkpoint, spec, seed, impacts_of)) {
    kept = std::move(*p);
    if (log)
      log(kept.build.finished
              ? fmt::format("sand gun: continuing from {}: its bed of {} spheres and {} finished impacts",
                            checkpoint, kept.bed.scene.bodies3d.size(), kept.done.size())
              : fmt::format("sand gun: continuing the bed's build from {}: {} stages done{} ({:.0f} s)",
                            checkpoint, kept.build.stage, stage_under_way(kept.build), kept.build.seconds));
  } else if (log) {
    log(fmt::format("sand gun: pouring {} sand spheres into {:.2f} x {:.2f} cm", spec.count, spec.width,
                    spec.depth));
  }
  finish_checkpointed_bed(
      kept, spec, seed,
      [&](const std::string& line) {
        if (log) log("sand gun: " + line);
      },
      checkpoint, impacts_of);
  out.bed = kept.bed;
  if (log)
    log(
        fmt::format("sand gun: bed top {:.3f} cm, packing {}, {} loose spheres taken away, {} probes, "
                    "{} holds, {} spheres still moving at the last ({:.0f} s)",
                    out.bed.top, packing_text(out.bed), out.bed.removed, out.bed.probes, build_holds(out.bed),
                    out.bed.deep_movers, out.bed.build_seconds));
  ImpactOptions o = sand_gun_options(spec);
  o.active_radius = active_zone * 2 * spec.radius;
  if (runs == 0) out.rows.clear();  // the bed only
  for (const SandGunRow& row : out.rows) {
    out.impacts.push_back(checkpoint.empty()
                              ? run_impact3d_ensemble(out.bed, sand_gun_case(row), seed, runs, o, progress)
                              : checkpointed_impacts(kept, row.index, kept.bed, sand_gun_case(row), runs,
                                                     seed, o, checkpoint, progress, impacts_of));
    out.quantities.push_back(sand_gun_quantities(out.impacts.back()));
    if (log)
      log(fmt::format("sand gun: row {} ({} cm/s, {} deg): {} impacts, {:.2f} ejecta each", row.index,
                      row.speed, row.alpha_deg, runs, out.quantities.back().at("ejecta").mean));
  }
  return out;
}

std::string sand_gun_impacts_of(double active_zone) {
  return active_zone > 0 ? fmt::format("{} {:.17g}", kActiveZoneKey, active_zone) : std::string();
}

void recount_sand_gun(SandGunRun& run, double visible_above) {
  run.visible_above = visible_above;
  for (std::size_t i = 0; i < run.rows.size(); ++i)
    run.quantities[i] = sand_gun_quantities(run.impacts[i], visible_above, 2 * run.bed.spec.radius);
}

std::vector<std::size_t> sand_gun_speed_series(const SandGunRun& run) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < run.rows.size(); ++i)
    if (run.rows[i].alpha_deg >= 15 && run.rows[i].alpha_deg <= 16) out.push_back(i);
  return out;
}

std::pair<PowerLaw, PowerLaw> sand_gun_exponent(const SandGunRun& run, const std::string& key) {
  std::vector<double> v, measured;
  std::vector<MeanInterval> ours;
  for (std::size_t i : sand_gun_speed_series(run)) {
    v.push_back(run.rows[i].speed);
    measured.push_back(run.rows[i].measured.at(key));
    ours.push_back(run.quantities[i].at(key));
  }
  return {fit_power_law(v, ours), fit_power_law(v, measured)};
}

namespace {
std::string table(const SandGunRun& run, const std::vector<std::pair<std::string, std::string>>& columns) {
  std::string md = "| v_i (cm/s) | alpha_i (deg) | impacts |";
  for (const auto& [k, label] : columns) md += " " + label + " |";
  md += "\n|---|---|---|";
  for (std::size_t k = 0; k < columns.size(); ++k) md += "---|";
  md += "\n";
  for (std::size_t i = 0; i < run.rows.size(); ++i) {
    const SandGunRow& row = run.rows[i];
    md += fmt::format("| {} | {} | {} ({}) |", row.speed, row.alpha_deg, run.impacts[i].size(), row.events);
    for (const auto& [k, label] : columns) {
      const MeanInterval& m = run.quantities[i].at(k);
      const std::string ours = m.n == 0 ? "-" : fmt::format("{:.3g} [{:.3g}, {:.3g}]", m.mean, m.lo, m.hi);
      md += fmt::format(" {} ({:.3g}) |", ours, row.measured.at(k));
    }
    md += "\n";
  }
  return md;
}
}  // namespace

std::string sand_gun_markdown(const SandGunRun& run) {
  const Bed3dSpec& s = run.bed.spec;
  std::string md = fmt::format(
      "Bed: {} spheres of diameter {:.3f}-{:.3f} cm (quartz, 2.65 g/cm^3, mu {}, restitution {}, k_n {:.3g} "
      "dyn/cm) poured into {:.2f} x {:.2f} cm; top {:.3f} cm, solid fraction {:.3f}, {} loose spheres taken "
      "away. Incident grain d = {:.3f} cm, followed for {:.4f} s. Each cell: grainlab's mean [95 % "
      "interval] (the experiment's mean); impacts: grainlab's (the experiment's events).\n\n",
      run.bed.scene.bodies3d.size(), 2 * s.smallest_radius(), 2 * s.largest_radius(), s.mu, s.restitution,
      s.k_n, s.width, s.depth, run.bed.top, run.bed.packing_fraction, run.bed.removed, 2 * kSandRadius,
      sand_gun_options(s).duration);
  if (run.active_zone > 0)
    md += fmt::format(
        "Only the bed grains within {:g} diameters of each impact point moved; the rest were held in "
        "place (--active-zone).\n\n",
        run.active_zone);
  md += "Table 3.11 (the rebound; angles from the vertical, in the incident plane):\n\n";
  md += table(run, {{"eps_ix", "eps_ix"},
                    {"eps_iy", "eps_iy"},
                    {"theta_i", "theta_i (deg)"},
                    {"energy_ratio", "E_out/E_in"}});
  md += "\nTable 3.12 (the ejecta; reptation = 2 v_x v_z / g at one diameter above the top";
  md += run.visible_above == 1
            ? "):\n\n"
            : fmt::format(
                  "; counted only if they rise {:g} diameters above the top, as the photographs' "
                  "apparent surface would have let them be seen):\n\n",
                  run.visible_above);
  md += table(run, {{"ejecta", "ejecta/event"},
                    {"reptation_event", "reptation/event (cm)"},
                    {"reptation", "reptation/ejectum (cm)"},
                    {"ej_vz", "v_ey (cm/s)"},
                    {"theta_e", "theta_e (deg)"}});
  if (sand_gun_speed_series(run).size() < 2) return md;
  md +=
      "\nPower laws in v_i over the rows at 15-16 deg (exponent +- 95 % half-width; experiment: its "
      "means):\n\n| quantity | grainlab | experiment |\n|---|---|---|\n";
  for (const auto& [k, label] : {std::pair{"ejecta", "ejecta/event"}, std::pair{"ej_vz", "v_ey"},
                                 std::pair{"reptation", "reptation/ejectum"}}) {
    const auto [ours, theirs] = sand_gun_exponent(run, k);
    md += fmt::format("| {} | {:.2f} +- {:.2f} | {:.2f} |\n", label, ours.exponent, ours.half_width,
                      theirs.exponent);
  }
  return md;
}

}  // namespace grainlab::validation
