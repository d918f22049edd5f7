#include "splash_measurement.hpp"

#include <fmt/format.h>

#include <cmath>

#include "ensemble.hpp"
#include "impacts.hpp"
#include "impacts3d.hpp"
#include "input_error.hpp"
#include "sand_gun3d.hpp"

namespace grainlab::validation {

namespace {

constexpr double kDeg = M_PI / 180;
constexpr const char* kWholeBed = "the whole bed";

saltation::SplashMoment moment(const MeanInterval& m) {
  return {m.mean, m.sd, m.lo, m.hi};
}

saltation::SplashCell make_cell(const std::vector<ImpactResult>& impacts, double speed_cm_s, double angle,
                                double u, double d) {
  saltation::SplashCell c;
  c.speed = speed_cm_s / u, c.angle_deg = angle, c.impacts = impacts.size();
  std::vector<double> ix, iy, ie, th, count, evx, evy, esp, ean, rep;
  std::size_t rebounds = 0;
  const double vx_in = speed_cm_s * std::cos(angle * kDeg), vy_in = speed_cm_s * std::sin(angle * kDeg);
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const ImpactResult& r = impacts[i];
    const double spin = r.spin * d / u;
    c.rebound.push_back({double(i), r.rebounded ? 1.0 : 0.0, r.rebounded ? r.vx / u : 0.0,
                         r.rebounded ? r.vy / u : 0.0, r.rebounded ? spin : 0.0});
    if (r.rebounded) {
      ++rebounds;
      ix.push_back(r.vx / vx_in), iy.push_back(r.vy / vy_in),
          ie.push_back(std::hypot(r.vx, r.vy) / speed_cm_s);
      th.push_back(std::atan2(r.vx, r.vy) / kDeg);
    }
    count.push_back(double(r.ejecta.size()));
    for (const Ejectum& e : r.ejecta) {
      c.ejecta.push_back({double(i), e.vx / u, e.vy / u, e.vx_launch / u, e.vy_launch / u, e.x0 / d, e.y0 / d,
                          double(static_cast<int>(e.type))});
      evx.push_back(e.vx_launch / u), evy.push_back(e.vy_launch / u);
      esp.push_back(std::hypot(e.vx_launch, e.vy_launch) / u);
      ean.push_back(std::atan2(e.vx_launch, e.vy_launch) / kDeg);
      rep.push_back(2 * e.vx * e.vy / r.g / d);
    }
  }
  CellSamples samples{impacts.size(), rebounds, ix, iy, ie, th, count, evx, evy, esp, ean, rep};
  set_cell_moments(c, samples);
  return c;
}

// A checkpoint continues only the measurement it came from: same grid, impacts, beds, seed and engine.
void check_resumable(const saltation::SplashFile& from, const saltation::SplashFile& now) {
  const auto differs = [&](const char* k) {
    const auto a = from.text.find(k), b = now.text.find(k);
    return a == from.text.end() || b == now.text.end() || a->second != b->second;
  };
  // ("active_zone" is absent from files written before zones: they moved the whole bed.)
  for (const char* k : {"runs_per_cell", "beds", "seed", "engine", "grainlab_version", "source"})
    if (differs(k))
      throw InputError({"--restart", 0}, k,
                       fmt::format("the checkpoint was made with {} = {}, this run has {}", k,
                                   from.text.count(k) ? from.text.at(k) : "(none)", now.text.at(k)));
  const auto zone = [](const saltation::SplashFile& f) {
    const auto z = f.text.find("active_zone");
    return z == f.text.end() ? std::string(kWholeBed) : z->second;
  };
  if (zone(from) != zone(now))
    throw InputError({"--restart", 0}, "active_zone",
                     fmt::format("the checkpoint's impacts moved {}, this run's move {} (--active-zone)",
                                 zone(from), zone(now)));
  if (from.dimension != now.dimension)
    throw InputError({"--restart", 0}, "dimension",
                     fmt::format("the checkpoint is {}-D, this run {}-D", from.dimension, now.dimension));
  if (from.speeds != now.speeds || from.angles_deg != now.angles_deg)
    throw InputError({"--restart", 0}, "grid", "the checkpoint's speeds or angles differ from this run's");
  if (from.cells.size() >= now.speeds.size() * now.angles_deg.size())
    throw InputError({"--restart", 0}, "complete", "the checkpoint already holds every cell");
}

}  // namespace

void set_cell_moments(saltation::SplashCell& c, const CellSamples& s) {
  const Proportion p = wilson_interval(s.rebounds, s.impacts);
  c.moments["rebound_probability"] = {p.p, std::sqrt(p.p * (1 - p.p)), p.lo, p.hi};
  const std::pair<const char*, const std::vector<double>*> stats[] = {
      {"eps_ix", &s.eps_ix},
      {"eps_iy", &s.eps_iy},
      {"eps_i", &s.eps_i},
      {"theta_i", &s.theta_i},
      {"ejecta_per_impact", &s.ejecta_per_impact},
      {"ejecta_vx", &s.ejecta_vx},
      {"ejecta_vy", &s.ejecta_vy},
      {"ejecta_speed", &s.ejecta_speed},
      {"ejecta_angle", &s.ejecta_angle},
      {"reptation_per_ejectum", &s.reptation_per_ejectum}};
  for (const auto& [name, v] : stats)
    if (!v->empty()) c.moments[name] = moment(mean_interval(*v));
}

SplashOptions quick_splash_options() {
  SplashOptions o;
  o.runs = 2, o.beds = 1;
  return o;
}

namespace {

// A 3-D cell: the incident plane is x-z, so z (vertical) goes to the file's y and y (across) to its lateral
// columns. Sphere beds mark no target, brink or anti-brink (type 0).
saltation::SplashCell make_cell3d(const std::vector<Impact3dResult>& impacts, double speed_cm_s, double angle,
                                  double u, double d) {
  saltation::SplashCell c;
  c.speed = speed_cm_s / u, c.angle_deg = angle, c.impacts = impacts.size();
  CellSamples s;
  s.impacts = impacts.size();
  std::vector<double> lateral, sideways;
  const double vx_in = speed_cm_s * std::cos(angle * kDeg), vz_in = speed_cm_s * std::sin(angle * kDeg);
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    const Impact3dResult& r = impacts[i];
    const double on = r.rebounded ? 1.0 : 0.0;
    c.rebound.push_back({double(i), on, on * r.vx / u, on * r.vz / u, 0.0});
    c.rebound_lateral.push_back(on * r.vy / u);
    if (r.rebounded) {
      ++s.rebounds;
      s.eps_ix.push_back(r.vx / vx_in), s.eps_iy.push_back(r.vz / vz_in);
      s.eps_i.push_back(std::sqrt(r.vx * r.vx + r.vy * r.vy + r.vz * r.vz) / speed_cm_s);
      s.theta_i.push_back(std::atan2(std::hypot(r.vx, r.vy), r.vz) / kDeg);
      lateral.push_back(r.vy / speed_cm_s);
    }
    s.ejecta_per_impact.push_back(double(r.ejecta.size()));
    for (const Ejectum3d& e : r.ejecta) {
      c.ejecta.push_back({double(i), e.vx / u, e.vz / u, e.vx / u, e.vz_launch / u, e.x0 / d, e.z0 / d, 0.0});
      c.ejecta_lateral.push_back({e.vy / u, e.y0 / d});
      s.ejecta_vx.push_back(e.vx / u), s.ejecta_vy.push_back(e.vz_launch / u);
      s.ejecta_speed.push_back(std::sqrt(e.vx * e.vx + e.vy * e.vy + e.vz_launch * e.vz_launch) / u);
      s.ejecta_angle.push_back(std::atan2(e.vx, e.vz_launch) / kDeg);
      s.reptation_per_ejectum.push_back(2 * e.vx * e.vz / r.g / d);
      sideways.push_back(std::abs(std::sin(std::atan2(e.vy, e.vx))));
    }
  }
  set_cell_moments(c, s);
  if (!lateral.empty()) c.moments["eps_lateral"] = moment(mean_interval(lateral));
  if (!sideways.empty()) c.moments["ejecta_sideways"] = moment(mean_interval(sideways));
  return c;
}

// The grid of cells, shared by both dimensions: skips the cells a checkpoint holds, checkpoints after
// each cell, stops early when asked. `cell` measures one (speed cm/s, angle, the cell's seed).
saltation::SplashFile measure_grid(
    saltation::SplashFile f, const SplashOptions& o,
    const std::function<saltation::SplashCell(double, double, std::uint64_t)>& cell) {
  const double u = f.velocity_scale();
  for (double v : o.speeds_cm_s) f.speeds.push_back(v / u);
  f.angles_deg = o.angles_deg;
  f.text["runs_per_cell"] = std::to_string(o.runs);
  f.text["beds"] = std::to_string(o.beds);
  if (o.resume) check_resumable(*o.resume, f), f.cells = o.resume->cells;
  std::size_t done = 0;
  for (double v : o.speeds_cm_s)
    for (double a : o.angles_deg) {
      if (done++ < f.cells.size()) continue;  // done before the checkpoint
      if (o.stop_after_cells > 0 && f.cells.size() >= o.stop_after_cells) {
        f.text["complete"] = "false";
        return f;
      }
      if (o.log) o.log(fmt::format("cell v_i = {} cm/s, alpha_i = {} deg: {} impacts", v, a, o.runs));
      // Each cell gets its own stream of impact points: seed and cell index.
      f.cells.push_back(cell(v, a, o.seed * 1000003 + f.cells.size()));
      if (o.checkpoint && f.cells.size() < o.speeds_cm_s.size() * o.angles_deg.size()) {
        saltation::SplashFile partial = f;
        partial.text["complete"] = "false";
        o.checkpoint(partial);
      }
    }
  return f;
}

// Bed k of a 3-D measurement: poured, or read from (and kept in) its bed checkpoint. The checkpoint's
// fingerprint names no impacts, so any splash run of the same bed spec can read it.
Bed3d splash_bed3d(const Bed3dSpec& spec, std::size_t k, const SplashOptions& o) {
  const auto say = [&](const std::string& line) {
    if (o.log) o.log(line);
  };
  const std::string which = fmt::format("sphere bed {} of {} ({} spheres in a {:g} x {:g} cm box)", k + 1,
                                        o.beds, spec.count, spec.width, spec.depth);
  if (o.bed_checkpoint.empty()) {
    say("pouring " + which);
    return build_bed3d(spec);
  }
  const std::string path = fmt::format("{}.bed-{}.h5", o.bed_checkpoint, k + 1);
  constexpr const char* kBedOnly = "splash bed";
  SandGunProgress kept;
  if (auto p = read_sand_gun_checkpoint(path, spec, 0, kBedOnly)) kept = std::move(*p);
  say(kept.build.finished ? fmt::format("read {} from {}", which, path)
                          : fmt::format("pouring {}, kept in {}", which, path));
  finish_checkpointed_bed(kept, spec, 0, say, path, kBedOnly);
  return kept.bed;
}

saltation::SplashFile measure_splash3d(const SplashOptions& o) {
  std::vector<Bed3d> beds;
  for (std::size_t k = 0; k < o.beds; ++k) {
    Bed3dSpec spec;
    if (o.box_width > 0) {
      spec.width = o.box_width, spec.depth = o.box_depth;
    } else {  // The box keeps its shape and its depth of spheres: its area scales with the count.
      const double scale = std::sqrt(o.spheres / double(spec.count));
      spec.width *= scale, spec.depth *= scale;
    }
    spec.count = o.spheres, spec.seed = k + 1;
    beds.push_back(splash_bed3d(spec, k, o));
  }
  const Bed3dSpec& bs = beds[0].spec;
  saltation::SplashFile f;
  f.dimension = 3;
  f.grain_diameter_cm = 2 * bs.radius, f.gravity_cm_s2 = 981, f.grain_density = bs.density;
  const double u = f.velocity_scale(), d = f.grain_diameter_cm;
  f.text = {
      {"kind", "simulated"},
      {"title", "splash function of grainlab's 3-D poured sphere beds (thesis Ch. III set-up with spheres)"},
      {"source",
       fmt::format("grainlab splash --dimension 3: impacts of an r_b sphere (no spin, mu 0.5) on poured "
                   "beds of {} spheres in a {} x {} cm box, followed 0.07 s; ejecta counted when their "
                   "centre rises one diameter above the top",
                   bs.count, bs.width, bs.depth)},
      {"engine", o.engine},
      {"grainlab_version", GRAINLAB_VERSION},
      {"seed", std::to_string(o.seed)},
      {"bed_preparation", fmt::format("poured spheres, {} bed(s), seeds 1..{}", o.beds, o.beds)},
      {"bed_scene", fmt::format("{} spheres of radius {} cm, density {} g/cm^3 (the thesis disc's mass), "
                                "k_n {:g}, restitution {}, mu {}",
                                bs.count, bs.radius, bs.density, bs.k_n, bs.restitution, bs.mu)},
      {"active_zone", o.active_zone > 0 ? fmt::format("the grains within {:g} diameters", o.active_zone)
                                        : std::string(kWholeBed)},
      {"notes",
       "3-D spheres: y is vertical as in 2-D files, the lateral columns hold the axis across the incident "
       "plane; spin is not recorded (0)"}};
  ImpactOptions io;
  io.engine = o.engine;
  io.active_radius = o.active_zone * 2 * bs.radius;
  return measure_grid(std::move(f), o, [&](double v, double a, std::uint64_t seed) {
    const ImpactCase c{fmt::format("{:.0f}cm/s-{:.0f}deg", v, a), v, a, 0.5, "loose", bs.radius};
    return make_cell3d(run_impact3d_ensemble(beds, c, seed, o.runs, io, o.progress), v, a, u, d);
  });
}

}  // namespace

saltation::SplashFile measure_splash(const SplashOptions& o) {
  if (o.dimension == 3) return measure_splash3d(o);
  std::vector<Bed> beds;
  for (std::size_t k = 0; k < o.beds; ++k) {
    BedSpec spec;
    spec.preparation = "loose", spec.seed = k + 1;
    if (o.log) o.log(fmt::format("building loose bed {} of {}", k + 1, o.beds));
    beds.push_back(build_bed(spec));
  }
  const BedSpec& bs = beds[0].spec;
  saltation::SplashFile f;
  f.grain_diameter_cm = 2 * bs.radius, f.gravity_cm_s2 = -beds[0].scene.gravity.y,
  f.grain_density = bs.density;
  const double u = f.velocity_scale(), d = f.grain_diameter_cm;
  f.text = {{"kind", "simulated"},
            {"title", "splash function of grainlab's 2-D loose impact beds (thesis Ch. III set-up)"},
            {"source",
             "grainlab splash: impacts of an r_b grain (no spin, mu 0.5) on 384-disc loose beds, "
             "followed 0.07 s; ejecta counted when their centre rises one diameter above the top"},
            {"engine", o.engine},
            {"grainlab_version", GRAINLAB_VERSION},
            {"seed", std::to_string(o.seed)},
            {"bed_preparation", fmt::format("loose, {} bed(s), seeds 1..{}", o.beds, o.beds)},
            {"bed_scene", beds[0].scene.text},
            {"notes", "2-D discs: density is per unit area (g/cm^2); grain_diameter_cm is the bed grain's"}};
  ImpactOptions io;
  io.engine = o.engine;
  return measure_grid(std::move(f), o, [&](double v, double a, std::uint64_t seed) {
    const ImpactCase c{fmt::format("{:.0f}cm/s-{:.0f}deg", v, a), v, a, 0.5, "loose", bs.radius};
    return make_cell(run_impact_ensemble(beds, c, seed, o.runs, io, o.progress).impacts, v, a, u, d);
  });
}

}  // namespace grainlab::validation
