#include "splash_measurement.hpp"

#include <fmt/format.h>

#include <cmath>

#include "ensemble.hpp"
#include "impacts.hpp"
#include "input_error.hpp"

namespace grainlab::validation {

namespace {

constexpr double kDeg = M_PI / 180;

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
  for (const char* k : {"runs_per_cell", "beds", "seed", "engine", "grainlab_version"})
    if (differs(k))
      throw InputError({"--restart", 0}, k,
                       fmt::format("the checkpoint was made with {} = {}, this run has {}", k,
                                   from.text.count(k) ? from.text.at(k) : "(none)", now.text.at(k)));
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

saltation::SplashFile measure_splash(const SplashOptions& o) {
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
  for (double v : o.speeds_cm_s) f.speeds.push_back(v / u);
  f.angles_deg = o.angles_deg;
  f.text["runs_per_cell"] = std::to_string(o.runs);
  f.text["beds"] = std::to_string(o.beds);
  if (o.resume) check_resumable(*o.resume, f), f.cells = o.resume->cells;
  ImpactOptions io;
  io.engine = o.engine;
  std::size_t cell = 0;
  for (double v : o.speeds_cm_s)
    for (double a : o.angles_deg) {
      if (cell++ < f.cells.size()) continue;  // done before the checkpoint
      if (o.stop_after_cells > 0 && f.cells.size() >= o.stop_after_cells) {
        f.text["complete"] = "false";
        return f;
      }
      ImpactCase c{fmt::format("{:.0f}cm/s-{:.0f}deg", v, a), v, a, 0.5, "loose", bs.radius};
      if (o.log) o.log(fmt::format("cell v_i = {} cm/s, alpha_i = {} deg: {} impacts", v, a, o.runs));
      // Each cell gets its own stream of impact points: seed and cell index.
      const std::uint64_t seed = o.seed * 1000003 + f.cells.size();
      const ImpactEnsemble e = run_impact_ensemble(beds, c, seed, o.runs, io, o.progress);
      f.cells.push_back(make_cell(e.impacts, v, a, u, d));
      if (o.checkpoint && f.cells.size() < o.speeds_cm_s.size() * o.angles_deg.size()) {
        saltation::SplashFile partial = f;
        partial.text["complete"] = "false";
        o.checkpoint(partial);
      }
    }
  return f;
}

}  // namespace grainlab::validation
