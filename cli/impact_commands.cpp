#include "impact_commands.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "active_zone_option.hpp"
#include "engine.hpp"
#include "engine_option.hpp"
#include "impact_bed.hpp"
#include "impacts.hpp"
#include "impacts3d.hpp"
#include "input_error.hpp"
#include "number_ranges.hpp"
#include "option_scope.hpp"
#include "output_path.hpp"
#include "parallel.hpp"
#include "plot_beside.hpp"
#include "progress.hpp"
#include "rebound_model.hpp"
#include "sand_gun3d.hpp"
#include "splash_file.hpp"
#include "splash_measurement.hpp"

namespace grainlab::cli {

namespace {

using namespace grainlab::validation;
namespace fs = std::filesystem;

// A single value has no spread: its sd and interval are null (and "-" in the tables), not zero.
nlohmann::json stat_json(const MeanInterval& m) {
  auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  auto spread = [&](double x) { return m.n > 1 ? num(x) : nlohmann::json(nullptr); };
  return {
      {"mean", num(m.mean)}, {"sd", spread(m.sd)}, {"lo", spread(m.lo)}, {"hi", spread(m.hi)}, {"n", m.n}};
}

nlohmann::json bed_json(const BedStats& s) {
  return {{"packing_fraction", s.packing_fraction},
          {"coordination", s.coordination},
          {"top", s.top},
          {"roughness", s.roughness},
          {"brinks", s.brinks},
          {"anti_brinks", s.anti_brinks},
          {"kinetic_energy", s.kinetic_energy},
          {"build_seconds", s.build_seconds}};
}

int bed_command(const ImpactCommands& a) {
  if (!a.bed_force && fs::exists(a.bed_out))
    throw InputError({"--out", 0}, a.bed_out, "exists; pass --force to overwrite it");
  if (!(a.width > 4) || a.count < 1)
    throw InputError({"--width", 0}, fmt::format("{}", a.width),
                     "the bed needs a width above 4 cm and discs");
  BedSpec spec;
  spec.preparation = a.preparation, spec.seed = a.bed_seed, spec.periodic = a.periodic;
  spec.width = a.width, spec.count = a.count, spec.levelled = !a.unlevelled;
  const Bed bed = build_bed(spec, [&](const std::string& line) {
    if (!a.bed_json) fmt::print(stderr, "grainlab bed: {}\n", line);
  });
  write_bed(bed, a.bed_out, a.bed_force);
  if (a.bed_json) {
    nlohmann::json j = bed_json(bed.stats);
    j["file"] = a.bed_out, j["preparation"] = spec.preparation, j["seed"] = spec.seed,
    j["count"] = spec.count;
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  const BedStats& s = bed.stats;
  fmt::print("wrote {} ({} bed, {} discs, seed {}, built in {:.1f} s)\n", a.bed_out, spec.preparation,
             spec.count, spec.seed, s.build_seconds);
  fmt::print(
      "  packing fraction {:.4f}, coordination {:.2f}, top {:.2f} cm, roughness {:.3f} cm, "
      "{} brinks, {} anti-brinks\n",
      s.packing_fraction, s.coordination, s.top, s.roughness, s.brinks, s.anti_brinks);
  return 0;
}

std::vector<Bed> beds_for(const ImpactCommands& a, const ImpactCase& c, bool speak) {
  std::vector<Bed> beds;
  for (const std::string& f : a.bed_files) beds.push_back(read_bed(f));
  if (!beds.empty()) return beds;
  for (std::size_t k = 0; k < a.beds; ++k) {
    BedSpec spec;
    spec.preparation = c.bed, spec.seed = k + 1;
    beds.push_back(build_bed(spec, [&](const std::string& line) {
      if (speak) fmt::print(stderr, "grainlab impact: bed {}: {}\n", k + 1, line);
    }));
  }
  return beds;
}

// Says how far the bed moved alone (when speaking; a 3-D bed also says where: `limits` are its at-rest
// limits) and stops unless it held (check_bed_held).
void report_bed_held(const BedHold& h, const std::string& engine, double duration, bool speak,
                     const std::optional<AtRestLimits>& limits = std::nullopt) {
  if (speak)
    fmt::print(stderr,
               "grainlab impact: {} holding the bed alone for {} s: largest displacement {:.3g} cm, "
               "largest speed {:.3g} cm/s, kinetic energy {:.3g} erg{}\n",
               engine, duration, h.max_displacement, h.max_speed, h.kinetic_energy,
               limits ? "; " + where_the_bed_moved(h, *limits) : "");
  check_bed_held(h, engine);
}

// Every quantity's mean, interval and spread beside the thesis's value (Tables 3.2-3.9), as a table on
// stdout or into `j` (the thesis's pair under `thesis_key`).
void print_quantities(const std::map<std::string, MeanInterval>& q,
                      const std::map<std::string, std::pair<double, double>>& thesis,
                      const std::string& mean_label, const std::string& thesis_label) {
  fmt::print("{:<16} {:>10} {:>20} {:>10} {:>20}\n", "quantity", mean_label, "95 % interval", "sd",
             thesis_label);
  for (const auto& [k, m] : q) {
    const std::string th =
        thesis.count(k) ? fmt::format("{:.3g} ({:.2g})", thesis.at(k).first, thesis.at(k).second) : "-";
    const bool spread = m.n > 1;
    fmt::print("{:<16} {:>10.4g} {:>20} {:>10} {:>20}\n", k, m.mean,
               spread ? fmt::format("[{:.4g}, {:.4g}]", m.lo, m.hi) : "-",
               spread ? fmt::format("{:.3g}", m.sd) : "-", th);
  }
}

void add_quantities(nlohmann::json& j, const std::map<std::string, MeanInterval>& q,
                    const std::map<std::string, std::pair<double, double>>& thesis,
                    const std::string& thesis_key) {
  for (const auto& [k, m] : q) {
    j[k] = stat_json(m);
    if (thesis.count(k)) j[k][thesis_key] = {thesis.at(k).first, thesis.at(k).second};
  }
}

// The 3-D bed, built here or taken from --checkpoint (the whole bed, or the stages of its build done so
// far); each stage is reported as it ends and kept in the checkpoint with every impact finished after it.
SandGunProgress checkpointed_bed3d(const ImpactCommands& a, const Bed3dSpec& spec,
                                   const std::string& impacts_of, bool speak) {
  SandGunProgress kept;
  if (!a.impact_checkpoint.empty()) {
    if (auto p = read_sand_gun_checkpoint(a.impact_checkpoint, spec, a.seed, impacts_of)) {
      kept = std::move(*p);
      if (speak)
        fmt::print(stderr, "grainlab impact: continuing from {}: {}\n", a.impact_checkpoint,
                   kept.build.finished ? fmt::format("its bed and {} finished impacts", kept.done.size())
                                       : fmt::format("the bed's build, {} stages done", kept.build.stage));
    }
  }
  finish_checkpointed_bed(
      kept, spec, a.seed,
      [&](const std::string& stage) {
        if (speak) fmt::print(stderr, "grainlab impact: {}\n", stage);
      },
      a.impact_checkpoint, impacts_of);
  return kept;
}

// Readies `bed` on the chosen engine: settled on the engine itself (--settle-on-engine), or held alone first
// (an impulse engine, or --hold), stopping when it did not hold. Returns the settles taken.
int ready_bed_on_engine(const ImpactCommands& a, Bed3d& bed, const ImpactOptions& o, bool speak) {
  if (a.settle_on_engine) {
    // The engine's own bed: an impulse engine squeezes the bed built here further (docs/impacts.md).
    EngineBed own =
        settle_on_engine(bed, a.engine, 0.2, 4, o.duration, o.rigid_dt, [&](const std::string& line) {
          if (speak) fmt::print(stderr, "grainlab impact: {}\n", line);
        });
    bed = std::move(own.bed);
    if (speak)
      fmt::print(stderr, "grainlab impact: settled the bed on {} {} x 0.2 s\n", a.engine, own.settles);
    report_bed_held(own.hold, a.engine, o.duration, speak, at_rest_limits(bed.spec));
    return own.settles;
  }
  if (a.engine != "native" || a.hold) {
    // An impulse engine must hold the bed at rest first, or its "ejecta" are the bed falling apart.
    const BedHold h = hold_bed3d(bed, a.engine, o.duration, o.rigid_dt);
    report_bed_held(h, a.engine, o.duration, speak, at_rest_limits(bed.spec));
  }
  return 0;
}

nlohmann::json impact3d_json(const ImpactCommands& a, const ImpactCase& c, const Bed3dSpec& spec,
                             const Bed3d& bed, int settles, const Impact3dSummary& s) {
  nlohmann::json j{{"case", c.name},
                   {"dimension", 3},
                   {"engine", a.engine},
                   {"runs", a.runs},
                   {"seed", a.seed},
                   {"spheres", spec.count},
                   {"grains", a.grains},
                   {"box", {spec.width, spec.depth}},
                   {"preparation", spec.preparation},
                   {"bed_top", bed.top},
                   {"packing_fraction", bed.packing_fraction},
                   {"spheres_removed", bed.removed},
                   {"bed_settles_on_engine", settles},
                   {"active_zone", a.active_zone},
                   {"rebounds", s.rebounds},
                   {"ejecta", s.ejecta},
                   {"median_wall_seconds", s.median_wall_seconds},
                   {"mean_steps", s.mean_steps}};
  add_quantities(j, s.q, thesis_impact_values(c.name), "thesis_2d");
  return j;
}

// `grainlab impact --dimension 3`: the case with spheres, beside the thesis's 2-D values.
int impact3d_command(const ImpactCommands& a, const ImpactCase& c) {
  if (!a.bed_files.empty())
    throw InputError({"--bed", 0}, a.bed_files[0], "bed files are 2-D; 3-D beds are poured here");
  const bool speak = !a.quiet && parallel::rank() == 0;  // (stderr: kept with --json)
  Bed3dSpec spec;
  spec.count = a.spheres;
  spec.seed = a.bed_seed;
  spec.preparation = c.bed;  // (CASE G's is dense: poured frictionless)
  spec.polyhedra = a.grains == "polyhedron";
  if (!a.box.empty()) spec.width = a.box[0], spec.depth = a.box[1];
  if (speak)
    fmt::print(stderr, "grainlab impact: pouring {} {} into a {} x {} cm box ({} bed)...\n", spec.count,
               spec.polyhedra ? "irregular grains" : "spheres", spec.width, spec.depth, spec.preparation);
  // The build takes minutes (an hour for irregular grains), so it can be checkpointed (in the sand gun's
  // file, as its row 1: the fingerprint holds the case, so no sand-gun run can take it for its own).
  const std::string impacts_of =
      fmt::format(
          "case {} speed {:.17g} alpha {:.17g} mu {:.17g} radius {:.17g} engine {} steps_per_contact {:.17g} "
          "settle_on_engine {}",
          c.name, c.speed, c.alpha_deg, c.mu, c.radius, a.engine, a.steps_per_contact, a.settle_on_engine) +
      (a.active_zone > 0 ? " " + sand_gun_impacts_of(a.active_zone) : std::string());
  SandGunProgress kept = checkpointed_bed3d(a, spec, impacts_of, speak);
  Bed3d bed = kept.bed;
  if (speak)
    fmt::print(stderr,
               "grainlab impact: bed top {:.2f} cm, packing {}, {} loose grains taken away ({:.1f} s); "
               "CASE {} (v_i {} cm/s, alpha_i "
               "{} deg, mu {}, r_i {} cm), {} impacts\n",
               bed.top, packing_text(bed), bed.removed, bed.build_seconds, c.name, c.speed, c.alpha_deg, c.mu,
               c.radius, a.runs);
  ImpactOptions o;
  o.engine = a.engine;
  o.steps_per_contact = a.steps_per_contact;
  o.active_radius = a.active_zone * 2 * spec.radius;
  const int settles = ready_bed_on_engine(a, bed, o, speak);
  ProgressBar bar(!a.quiet && parallel::rank() == 0, "impacts");  // (stderr: kept with --json)
  const EnsembleProgress tick = [&](std::size_t d, std::size_t t) {
    bar.update(static_cast<double>(d), static_cast<double>(t));
  };
  const auto results =
      a.impact_checkpoint.empty()
          ? run_impact3d_ensemble(bed, c, a.seed, a.runs, o, tick)
          : checkpointed_impacts(kept, 1, bed, c, a.runs, a.seed, o, a.impact_checkpoint, tick, impacts_of);
  bar.finish();
  if (!a.record.empty() && parallel::rank() == 0) {
    ImpactOptions ro = o;
    ro.record = a.record, ro.overwrite = a.force;
    run_impact3d(bed, c, a.seed, 0, ro);
  }
  if (parallel::rank() != 0) return 0;
  const Impact3dSummary s = summarize_impacts3d(results);
  if (a.impact_json) {
    fmt::print("{}\n", impact3d_json(a, c, spec, bed, settles, s).dump(2));
    return 0;
  }
  fmt::print(
      "CASE {} with {}: {} impacts, {} rebounded, {} ejecta; median {:.2f} s per impact ({:.0f} "
      "steps)\n",
      c.name, spec.polyhedra ? "irregular grains" : "spheres", s.impacts, s.rebounds, s.ejecta,
      s.median_wall_seconds, s.mean_steps);
  print_quantities(s.q, thesis_impact_values(c.name), "3-D mean", "thesis 2-D (spread)");
  return 0;
}

// --active-zone holds grains in place: spheres (3-D) on the native engine only.
void check_active_zone(double zone, int dimension, const std::string& engine) {
  if (zone > 0 && dimension != 3)
    throw InputError({"--active-zone", 0}, fmt::format("{:g}", zone),
                     "is for --dimension 3 (a 2-D impact moves its whole bed)");
  if (zone > 0 && engine != "native")
    throw InputError(
        {"--active-zone", 0}, fmt::format("{:g}", zone),
        fmt::format("holds grains in place, which only the native engine does (not {})", engine));
}

// The options whose help begins "--dimension 3" change nothing in a 2-D run: name them rather than run
// discs as if `--grains polyhedron` or `--spheres 5000` had been heard.
void refuse_3d_options(const CLI::App* cmd, int dimension) {
  if (dimension == 3) return;
  for (const CLI::Option* o : cmd->get_options())
    if (o->get_description().starts_with("--dimension 3"))
      refuse_if_given(o, fmt::format("is for --dimension 3 (this run is --dimension {})", dimension));
}

// An engine that does not simulate the asked dimension is named before a bed is poured (a 3-D pour takes a
// minute; box2d was refused only after it).
void check_engine_dimension(const std::string& engine, int dimension) {
  const auto simulates = [dimension](const std::string& e) {
    const auto& d = engine_capabilities(e).dimensions;
    return std::find(d.begin(), d.end(), dimension) != d.end();
  };
  if (simulates(engine)) return;
  std::vector<std::string> able;
  for (const std::string& e : engine_names())
    if (simulates(e)) able.push_back(e);
  throw InputError({"--engine", 0}, engine,
                   fmt::format("does not simulate {}-D beds; --dimension {} runs on {}", dimension, dimension,
                               fmt::join(able, ", ")));
}

int impact_command(const ImpactCommands& a) {
  const ImpactCase& c = impact_case(a.case_name);
  if (!a.record.empty() && !a.force && fs::exists(a.record))
    throw InputError({"--record", 0}, a.record, "exists; pass --force to overwrite it");
  check_active_zone(a.active_zone, a.dimension, a.engine);
  refuse_3d_options(a.impact_cmd, a.dimension);
  check_engine_dimension(a.engine, a.dimension);
  if (!engine_capabilities(a.engine).soft_contacts)
    refuse_if_given(a.impact_cmd->get_option("--steps-per-contact"),
                    fmt::format("is for soft-contact engines (native); {} steps at its fixed dt", a.engine));
  if (a.dimension == 3) return impact3d_command(a, c);
  const bool speak = !a.quiet && parallel::rank() == 0;  // (stderr: kept with --json)
  const std::vector<Bed> beds = beds_for(a, c, speak);
  ImpactOptions o;
  o.engine = a.engine;
  o.steps_per_contact = a.steps_per_contact;
  if (a.engine != "native") {
    // An impulse engine must hold the bed at rest first, or its "ejecta" are the bed falling apart.
    const BedHold h = hold_bed(beds[0], a.engine, o.duration, o.rigid_dt);
    report_bed_held(h, a.engine, o.duration, speak);
  }
  ProgressBar bar(!a.quiet && parallel::rank() == 0, "impacts");  // (stderr: kept with --json)
  if (speak)
    fmt::print(stderr,
               "grainlab impact: CASE {} (v_i {} cm/s, alpha_i {} deg, mu {}, r_i {} cm), {} impacts on "
               "{} {} bed(s), engine {}{}\n",
               c.name, c.speed, c.alpha_deg, c.mu, c.radius, a.runs, beds.size(), c.bed, a.engine,
               parallel::size() > 1 ? fmt::format(", {} MPI ranks", parallel::size()) : "");
  if (speak && !a.impact_checkpoint.empty())
    fmt::print(stderr, "grainlab impact: {} {}\n",
               fs::exists(a.impact_checkpoint) ? "continuing from" : "keeping every finished impact in",
               a.impact_checkpoint);
  const ImpactEnsemble e = run_impact_ensemble(
      beds, c, a.seed, a.runs, o,
      [&](std::size_t d, std::size_t t) { bar.update(static_cast<double>(d), static_cast<double>(t)); },
      a.impact_checkpoint);
  bar.finish();
  if (!a.record.empty() && parallel::rank() == 0) {
    ImpactOptions ro = o;
    ro.record = a.record, ro.overwrite = a.force;
    run_impact(beds[0], c, a.seed, 0, ro);
  }
  if (parallel::rank() != 0) return 0;
  const ImpactSummary s = summarize_impacts(e.impacts, beds[0].spec.restitution);
  const auto thesis = thesis_impact_values(c.name);
  if (a.impact_json) {
    nlohmann::json j{{"case", c.name},
                     {"engine", a.engine},
                     {"runs", a.runs},
                     {"seed", a.seed},
                     {"rebounds", s.rebounds},
                     {"ejecta", s.ejecta},
                     {"beds", beds.size()},
                     {"median_wall_seconds", s.median_wall_seconds},
                     {"mean_steps", s.mean_steps},
                     {"ejecta_dropped", e.ejecta_dropped}};
    add_quantities(j, s.q, thesis, "thesis");
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("CASE {}: {} impacts, {} rebounded, {} ejecta; median {:.2f} s per impact ({:.0f} steps)\n",
             c.name, s.impacts, s.rebounds, s.ejecta, s.median_wall_seconds, s.mean_steps);
  print_quantities(s.q, thesis, "mean", "thesis (spread)");
  return 0;
}

int rebound_command(const ImpactCommands& a) {
  if (a.model_case != 1 && a.model_case != 2)
    throw InputError({"--case", 0}, std::to_string(a.model_case), "must be 1 or 2 (Table 3.10)");
  ReboundParams p = rebound_case(a.model_case, a.alpha);
  if (a.mass_ratio) p.mass_ratio = *a.mass_ratio;  // (ranges checked as the command line is read)
  if (a.sigma) p.sigma = *a.sigma;
  p.spin = a.spin, p.bed_gap = a.gap, p.radius_ratio = a.radius_ratio;
  const ReboundAverages r = rebound_model(p);
  if (a.model_json) {
    fmt::print("{}\n", nlohmann::json{{"case", a.model_case},
                                      {"alpha", a.alpha},
                                      {"mass_ratio", p.mass_ratio},
                                      {"sigma", p.sigma},
                                      {"eps_ix", r.eps_ix},
                                      {"eps_iy", r.eps_iy},
                                      {"eps_i", r.eps_i},
                                      {"theta_i", r.theta_i_deg},
                                      {"beta", r.beta_deg},
                                      {"nabbed_fraction", r.nabbed_fraction},
                                      {"below_one_fraction", r.below_one_fraction}}
                           .dump(2));
    return 0;
  }
  fmt::print("rebound model (thesis Appendix III.1), CASE {} of Table 3.10 at alpha_i = {} deg\n",
             a.model_case, a.alpha);
  fmt::print("  m_i/m_beff {}, sigma {}, eps {}, kappa_beff {}, r_i/r_b {}, gap {} r_b, spin w r/v {}\n",
             p.mass_ratio, p.sigma, p.restitution, p.kappa_beff, p.radius_ratio, p.bed_gap, p.spin);
  fmt::print("  mean eps_ix {:.4f}, eps_iy {:.4f}, eps_i {:.4f}, theta_i {:.2f} deg, beta {:.2f} deg\n",
             r.eps_ix, r.eps_iy, r.eps_i, r.theta_i_deg, r.beta_deg);
  fmt::print("  nabbed {:.3f}, eps_iy < 1 in {:.3f} of impacts\n", r.nabbed_fraction, r.below_one_fraction);
  return 0;
}

// Where an unfinished measurement is kept: --checkpoint, or beside --out.
std::string splash_checkpoint_path(const ImpactCommands& a) {
  return a.splash_checkpoint.empty() ? a.splash_out + ".checkpoint.h5" : a.splash_checkpoint;
}

// Refuses options that do not go together (3-D ones on a 2-D measurement, an engine without the dimension).
void check_splash_options(const ImpactCommands& a) {
  if (!a.splash_force && fs::exists(a.splash_out))
    throw InputError({"--out", 0}, a.splash_out, "exists; pass --force to overwrite it");
  if (!a.sand_gun) check_active_zone(a.splash_active_zone, a.splash_dimension, a.splash_engine);
  if (!a.splash_bed_checkpoint.empty() && a.splash_dimension != 3)
    throw InputError({"--bed-checkpoint", 0}, a.splash_bed_checkpoint,
                     "is for --dimension 3 (a 2-D bed is built in seconds)");
  if (!a.splash_box.empty() && a.splash_dimension != 3)
    throw InputError({"--box", 0}, fmt::format("{:g} {:g}", a.splash_box[0], a.splash_box[1]),
                     "is for --dimension 3 (the 2-D beds are the thesis's)");
  if (!a.sand_gun) {
    refuse_3d_options(a.splash_cmd, a.splash_dimension);
    check_engine_dimension(a.splash_engine, a.splash_dimension);
  }
}

// The splash measured by impacts on the grid of speeds and angles, checkpointed after every cell.
saltation::SplashFile measure_splash_cells(const ImpactCommands& a, bool speak) {
  SplashOptions o = a.splash_quick ? quick_splash_options() : SplashOptions{};
  if (a.splash_runs > 0) o.runs = a.splash_runs;
  if (a.splash_beds > 0) o.beds = a.splash_beds;
  o.seed = a.splash_seed, o.engine = a.splash_engine;
  o.dimension = a.splash_dimension, o.spheres = a.splash_spheres;
  if (!a.splash_box.empty()) o.box_width = a.splash_box[0], o.box_depth = a.splash_box[1];
  o.active_zone = a.splash_active_zone;
  o.bed_checkpoint = a.splash_bed_checkpoint;
  if (!a.splash_speeds.empty()) o.speeds_cm_s = a.splash_speeds;
  if (!a.splash_angles.empty()) o.angles_deg = a.splash_angles;
  saltation::SplashFile resume;
  if (!a.splash_restart.empty()) {
    resume = saltation::read_splash_file(a.splash_restart, true);
    o.resume = &resume;
  }
  const std::string checkpoint = splash_checkpoint_path(a);
  if (parallel::rank() == 0)
    o.checkpoint = [&](const saltation::SplashFile& partial) {
      saltation::write_splash_file(checkpoint, partial, true);
    };
  o.stop_after_cells = a.splash_stop_after;
  ProgressBar bar(!a.splash_quiet && parallel::rank() == 0, "impacts");  // (stderr: kept with --json)
  if (speak)
    o.log = [&](const std::string& line) { bar.finish(), fmt::print(stderr, "grainlab splash: {}\n", line); };
  o.progress = [&](std::size_t d, std::size_t t) { bar.update(double(d), double(t)); };
  return measure_splash(o);
}

nlohmann::json splash_json(const std::string& path, const saltation::SplashFile& f) {
  nlohmann::json cells = nlohmann::json::array();
  for (const auto& c : f.cells) {
    nlohmann::json m;
    for (const auto& [k, v] : c.moments) m[k] = {{"mean", v.mean}, {"sd", v.sd}, {"lo", v.lo}, {"hi", v.hi}};
    cells.push_back({{"speed", c.speed},
                     {"angle", c.angle_deg},
                     {"impacts", c.impacts},
                     {"ejecta", c.ejecta.size()},
                     {"moments", m}});
  }
  return {{"file", path},
          {"schema", f.text.at("schema")},
          {"kind", f.text.at("kind")},
          {"velocity_scale_cm_s", f.velocity_scale()},
          {"grain_diameter_cm", f.grain_diameter_cm},
          {"cells", cells}};
}

void print_splash_table(const std::string& path, const saltation::SplashFile& f) {
  fmt::print("wrote {} ({}, {} cells, velocity scale sqrt(g d) = {:.4g} cm/s)\n", path, f.text.at("kind"),
             f.cells.size(), f.velocity_scale());
  fmt::print("{:>8} {:>6} {:>8} {:>10} {:>8} {:>12} {:>10}\n", "v/sqrt(gd)", "alpha", "impacts", "P(rebound)",
             "eps_iy", "ejecta/imp", "ej v_y");
  for (const auto& c : f.cells) {
    auto m = [&](const char* k) { return c.moments.count(k) ? c.moments.at(k).mean : std::nan(""); };
    fmt::print("{:>8.3g} {:>6.0f} {:>8} {:>10.3g} {:>8.3g} {:>12.3g} {:>10.3g}\n", c.speed, c.angle_deg,
               c.impacts, m("rebound_probability"), m("eps_iy"), m("ejecta_per_impact"), m("ejecta_vy"));
  }
}

int splash_command(const ImpactCommands& a) {
  check_splash_options(a);
  const bool speak = !a.splash_quiet && parallel::rank() == 0;  // (stderr: kept with --json)
  const saltation::SplashFile f = a.sand_gun ? saltation::sand_gun_splash() : measure_splash_cells(a, speak);
  if (parallel::rank() != 0) return 0;
  if (f.text.count("complete")) {
    if (!a.splash_quiet)
      fmt::print(stderr, "grainlab splash: stopped after {} cells as asked; continue with --restart {}\n",
                 f.cells.size(), splash_checkpoint_path(a));
    return 0;
  }
  saltation::write_splash_file(a.splash_out, f, a.splash_force);
  if (!a.sand_gun) {  // finished: the checkpoint is no longer needed
    const std::string checkpoint = splash_checkpoint_path(a);
    if (checkpoint != a.splash_restart) fs::remove(checkpoint);
  }
  const saltation::SplashFile back = saltation::read_splash_file(a.splash_out);  // what a model will read
  draw_plot_beside(a.splash_out, "_splash", "plot_splash.py", {a.splash_out}, a.splash_force, a.splash_json,
                   "heat maps of the ejecta per incident cell");
  if (a.splash_json)
    fmt::print("{}\n", splash_json(a.splash_out, back).dump(2));
  else
    print_splash_table(a.splash_out, back);
  return 0;
}

}  // namespace

void ImpactCommands::add(CLI::App& app) {
  add_bed(app);
  add_impact(app);
  add_splash(app);
  add_rebound_model(app);
}

void ImpactCommands::add_bed(CLI::App& app) {
  bed_cmd = app.add_subcommand("bed", "build a Ch. III impact bed (384 discs, loose or dense) as a run file");
  bed_cmd
      ->add_option("--preparation", preparation,
                   "loose (poured with friction) or dense (poured frictionless)")
      ->default_val("loose")
      ->check(CLI::IsMember({"loose", "dense"}));
  bed_cmd->add_option("--seed", bed_seed, "seed of the pour")->default_val(1);
  bed_cmd->add_flag("--periodic", periodic, "periodic in x (a floor, no side walls)");
  bed_cmd->add_flag("--unlevelled", unlevelled, "keep the poured surface (no scraping)");
  bed_cmd->add_option("--width", width, "box width or period, cm")->default_val(67.3)->check(cli::positive());
  bed_cmd->add_option("--count", count, "discs")->default_val(384)->check(cli::in_range(1, 1000000));
  bed_cmd->add_option("--out,-o", bed_out, "the bed's run file (.h5 + .xmf)")
      ->check(cli::output_file())
      ->required();
  bed_cmd->add_flag("--force", bed_force, "overwrite an existing file");
  bed_cmd->add_flag("--json", bed_json, "print the bed's statistics as JSON");
}

void ImpactCommands::add_impact(CLI::App& app) {
  impact_cmd =
      app.add_subcommand("impact", "impacts of one case of Table 3.1 on a bed; thesis Tables 3.2-3.9");
  impact_cmd->add_option("--case", case_name, "A..I")->required();
  add_engine_option(impact_cmd, engine, "engine");
  impact_cmd->add_option("--runs", runs, "impacts (spread over MPI ranks)")
      ->default_val(10)
      ->check(cli::in_range(1, 100000));
  impact_cmd->add_option("--seed", seed, "seed: impact i draws its point from (seed, i)")->default_val(1);
  impact_cmd
      ->add_option("--bed", bed_files, "bed file from `grainlab bed` (repeatable; impact i uses bed i mod N)")
      ->check(CLI::ExistingFile);
  impact_cmd->add_option("--beds", beds, "without --bed: build this many beds of the case's preparation")
      ->default_val(1)
      ->check(cli::in_range(1, 100));
  impact_cmd
      ->add_option("--steps-per-contact", steps_per_contact, "native: Verlet steps per shortest contact time")
      ->default_val(30)
      ->check(cli::in_range(5.0, 1000.0));
  impact_cmd->add_option("--record", record, "also write impact 0 as a run file (ParaView)")
      ->check(cli::output_file());
  impact_cmd->add_flag("--force", force, "overwrite the --record file");
  impact_cmd->add_flag("--json", impact_json, "print one JSON object with every quantity");
  impact_cmd->add_option("--dimension", dimension, "2 (discs, the thesis) or 3 (spheres, a poured bed)")
      ->default_val(2)
      ->check(CLI::IsMember({2, 3}));
  add_active_zone_option(impact_cmd, active_zone, "--dimension 3, native: ");
  impact_cmd
      ->add_option("--checkpoint", impact_checkpoint,
                   "keep every finished impact in this file (and, with --dimension 3, the bed's build: each "
                   "stage, and every 10 min within one); run the same command again to continue from it "
                   "(--runs may grow)")
      ->check(cli::output_file());
  impact_cmd->add_option("--spheres", spheres, "--dimension 3: spheres poured into the 67.3 x 20 cm box")
      ->default_val(2000)
      ->check(cli::in_range(100, 1000000));
  impact_cmd->add_option("--bed-seed", bed_seed, "--dimension 3: seed of the pour")->default_val(1);
  impact_cmd
      ->add_option("--grains", grains,
                   "--dimension 3: sphere, or polyhedron (irregular convex grains of the spheres' volumes, "
                   "on the general 3-D path: hundreds of times slower)")
      ->default_val("sphere")
      ->check(CLI::IsMember({"sphere", "polyhedron"}));
  impact_cmd->add_option("--box", box, "--dimension 3: the box's x and y in cm (default 67.3 20)")
      ->expected(2)
      ->check(cli::positive());
  impact_cmd->add_flag(
      "--hold", hold,
      "--dimension 3: first run the bed alone for 0.07 s and report (and check) how far it moves "
      "(always done for impulse engines)");
  impact_cmd->add_flag("--settle-on-engine", settle_on_engine,
                       "--dimension 3: settle the bed on --engine itself first (0.2 s at a time, until it "
                       "holds still, at most 4 times): ODE and Bullet squeeze a bed built on the native "
                       "engine further, so it does not hold still on them as built");
  impact_cmd->add_flag("--quiet,-q", quiet, "no progress");
}

void ImpactCommands::add_splash(CLI::App& app) {
  splash_cmd = app.add_subcommand("splash",
                                  "measure the splash function over incident speed and angle; write a "
                                  "grainlab-splash/1 file for the saltation and ripple models");
  splash_cmd->add_option("--out,-o", splash_out, "the splash file (.h5)")
      ->check(cli::output_file())
      ->required();
  splash_cmd->add_flag("--quick", splash_quick, "2 impacts per cell on one bed (for CI)");
  splash_cmd->add_option("--runs", splash_runs, "impacts per cell (default 100; quick 2)")
      ->check(cli::in_range(1, 100000));
  splash_cmd->add_option("--beds", splash_beds, "independent loose beds (default 3; quick 1)")
      ->check(cli::in_range(1, 100));
  splash_cmd->add_option("--seed", splash_seed, "seed of the impact points")->default_val(1);
  add_engine_option(splash_cmd, splash_engine, "engine");
  splash_cmd->add_option("--speeds", splash_speeds, "incident speeds, cm/s (default 300 1000 2000 4000 8100)")
      ->check(cli::positive());
  splash_cmd
      ->add_option("--angles", splash_angles,
                   "incident angles from the horizontal, deg (default 5 15 25 45 70)")
      ->check(cli::in_range(0.0, 90.0, Ends::open));
  splash_cmd
      ->add_option("--checkpoint", splash_checkpoint,
                   "checkpoint after every cell (default OUT.checkpoint.h5)")
      ->check(cli::output_file());
  splash_cmd->add_option("--restart", splash_restart, "continue from a checkpoint")->check(CLI::ExistingFile);
  splash_cmd
      ->add_option("--stop-after-cells", splash_stop_after, "stop unfinished after N cells (then --restart)")
      ->check(cli::non_negative());
  splash_cmd
      ->add_option("--dimension", splash_dimension, "2 (discs, the thesis's beds) or 3 (poured spheres)")
      ->default_val(2)
      ->check(CLI::IsMember({2, 3}));
  splash_cmd
      ->add_option("--spheres", splash_spheres,
                   "--dimension 3: spheres per bed (2,000 fill the 67.3 x 20 cm box; others scale its area)")
      ->default_val(2000)
      ->check(cli::in_range(100, 1000000));
  splash_cmd
      ->add_option("--box", splash_box,
                   "--dimension 3: the box's x and y in cm, filled with --spheres (default: 67.3 x 20 "
                   "scaled to --spheres)")
      ->expected(2)
      ->check(cli::positive());
  add_active_zone_option(splash_cmd, splash_active_zone, "--dimension 3, native: ");
  splash_cmd
      ->add_option("--bed-checkpoint", splash_bed_checkpoint,
                   "--dimension 3: keep each poured bed in PREFIX.bed-K.h5 and read it from there next time "
                   "(same box, spheres and bed): a big bed is poured once for every run, zone and restart")
      ->check(cli::output_file());
  splash_cmd->add_flag("--sand-gun", sand_gun,
                       "write the thesis's sand-gun measurements (Tables 3.11, 3.12) instead");
  splash_cmd->add_flag("--force", splash_force, "overwrite an existing file");
  splash_cmd->add_flag("--json", splash_json, "print the cells' moments as JSON");
  splash_cmd->add_flag("--quiet,-q", splash_quiet, "no progress");
}

void ImpactCommands::add_rebound_model(CLI::App& app) {
  rebound_cmd =
      app.add_subcommand("rebound-model", "the thesis's rebound model (Appendix III.1, Table 3.10)");
  rebound_cmd->add_option("--case", model_case, "1 or 2 (Table 3.10)")->default_val(2);
  rebound_cmd->add_option("--alpha", alpha, "incident angle from the horizontal, degrees")
      ->default_val(15)
      ->check(cli::in_range(0.0, 90.0, Ends::open));
  rebound_cmd->add_option("--mass-ratio", mass_ratio, "m_i / m_beff (default: the case's 0.5)")
      ->check(cli::positive());
  rebound_cmd->add_option("--sigma", sigma, "friction restitution (default: the case's)")
      ->check(cli::in_range(-1.0, 1.0));
  rebound_cmd->add_option("--spin", spin, "incident spin w_i r_i / v_i (counter-clockwise positive)")
      ->default_val(0);
  rebound_cmd->add_option("--gap", gap, "gap between bed discs, in r_b")
      ->default_val(0)
      ->check(cli::non_negative());
  rebound_cmd->add_option("--radius-ratio", radius_ratio, "r_i / r_b")
      ->default_val(1)
      ->check(cli::positive());
  rebound_cmd->add_flag("--json", model_json, "print {eps_ix, eps_iy, theta_i, beta, nabbed_fraction, ...}");
}

int ImpactCommands::dispatch() const {
  if (splash_cmd && *splash_cmd) return splash_command(*this);
  if (bed_cmd && *bed_cmd) return bed_command(*this);
  if (impact_cmd && *impact_cmd) return impact_command(*this);
  if (rebound_cmd && *rebound_cmd) return rebound_command(*this);
  return -1;
}

}  // namespace grainlab::cli
