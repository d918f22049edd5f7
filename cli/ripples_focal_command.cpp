// `grainlab ripples hybrid-focal`: flat-bed flux runs of the 3-D hybrid model at several u*, their
// window-mean wind profiles, the roughness z0 of each profile's log layer, and the focal point the profiles
// share (Huo et al. 2021, Fig. 14 and eq. 32: z0 = z_F exp(-kappa u_F / u*); docs/hybrid.md).
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "focal_point.hpp"
#include "h5_output.hpp"
#include "hybrid_splash_file.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
#include "report.hpp"
#include "ripples_commands.hpp"

namespace grainlab::cli {

namespace {

using ripples::hybrid::FluxResult;
using ripples::hybrid::FocalPoint;
using ripples::hybrid::WindProfile;

void check_focal_options(const RipplesCommands& a) {
  const ripples::hybrid::FluxOptions& o = a.flux;
  if (a.focal_ustars.size() < 2)
    throw InputError({"--ustar", 0}, fmt::format("{} value(s)", a.focal_ustars.size()),
                     "a focal point needs at least two wind speeds");
  for (std::size_t i = 0; i < a.focal_ustars.size(); ++i)
    for (std::size_t j = i + 1; j < a.focal_ustars.size(); ++j)
      if (a.focal_ustars[i] == a.focal_ustars[j])
        throw InputError({"--ustar", 0}, fmt::format("{}", a.focal_ustars[i]), "is given twice");
  const double top = o.height;
  if (!(a.focal_band[0] > 0 && a.focal_band[0] < a.focal_band[1] && a.focal_band[1] <= top))
    throw InputError(
        {"--log-band", 0}, fmt::format("{} {}", a.focal_band[0], a.focal_band[1]),
        fmt::format("must be two heights in d with 0 < low < high <= the column's top ({})", top));
  if (!(a.focal_above < top))
    throw InputError({"--focus-above", 0}, fmt::format("{}", a.focal_above),
                     fmt::format("must be below the column's top ({} d): no profile crosses above it", top));
  check_flux_options(o);
}

// The plots: the profiles (u against log z, the focal point marked) and ln z0 against 1 / u* with its line.
std::vector<validation::PlotSpec> focal_plots(const std::vector<WindProfile>& p, const FocalPoint& f,
                                              double d) {
  using validation::PlotSpec;
  PlotSpec profiles{"focal_profiles.png",
                    "Wind over saltation (window means) and the focal point",
                    "u (cm/s)",
                    "z (d)",
                    false,
                    {}};
  profiles.logy = true;
  for (const WindProfile& w : p) {
    PlotSpec::Series s{fmt::format("u* = {:g} cm/s", w.u_star), "line", {}, {}, {}};
    for (std::size_t k = 0; k < w.z.size(); ++k)
      if (w.z[k] >= 0.01 * d) s.x.push_back(w.u[k]), s.y.push_back(w.z[k] / d);
    profiles.series.push_back(s);
  }
  PlotSpec::Series cross{"profiles cross", "points", {}, {}, {}};
  for (const auto& c : f.crossings) cross.x.push_back(c.u), cross.y.push_back(c.z / d);
  PlotSpec::Series fit{"eq. 32 fit (z_F, u_F)", "points", {f.fit_u}, {f.fit_z / d}, {}};
  profiles.series.push_back(cross), profiles.series.push_back(fit);
  PlotSpec z0{"focal_z0.png",  "Roughness of the log layer: ln z0 = ln z_F - kappa u_F / u* (eq. 32)",
              "1 / u* (s/cm)", "z0 (d)",
              false,           {}};
  z0.logy = true;
  PlotSpec::Series measured{"log-layer fits", "points", {}, {}, {}},
      line{"least squares", "line", {}, {}, {}};
  for (std::size_t k = 0; k < p.size(); ++k)
    measured.x.push_back(1 / p[k].u_star), measured.y.push_back(f.log_layers[k].z0 / d);
  const auto [lo, hi] = std::minmax_element(measured.x.begin(), measured.x.end());
  for (int k = 0; k <= 20; ++k) {
    const double x = *lo + (*hi - *lo) * k / 20.0;
    line.x.push_back(x),
        line.y.push_back(f.fit_z * std::exp(-ripples::hybrid::WindColumn::kKappa * f.fit_u * x) / d);
  }
  z0.series = {measured, line};
  return {profiles, z0};
}

std::string profiles_csv(const std::vector<WindProfile>& p, double d) {
  std::string csv = "z_cm,z_d";
  for (const WindProfile& w : p) csv += fmt::format(",u_ustar_{:g}", w.u_star);
  csv += "\n";
  for (std::size_t k = 0; k < p.front().z.size(); ++k) {
    csv += fmt::format("{:.6g},{:.6g}", p.front().z[k], p.front().z[k] / d);
    for (const WindProfile& w : p) csv += fmt::format(",{:.6g}", w.u[k]);
    csv += "\n";
  }
  return csv;
}

nlohmann::json focal_json(const RipplesCommands& a, const std::vector<FluxResult>& runs,
                          const std::vector<WindProfile>& p, const FocalPoint& f) {
  const double d = a.flux.diameter;
  nlohmann::json rows = nlohmann::json::array(), crossings = nlohmann::json::array();
  for (std::size_t k = 0; k < p.size(); ++k)
    rows.push_back({{"u_star", p[k].u_star},
                    {"shields", runs[k].shields},
                    {"mass_flux_star", runs[k].mass_flux_star},
                    {"airborne", runs[k].airborne},
                    {"u_star_bed", runs[k].u_star_bed},
                    {"z0_d", f.log_layers[k].z0 / d},
                    {"log_layer_spread", f.log_layers[k].spread},
                    {"log_layer_nodes", f.log_layers[k].nodes}});
  for (const auto& c : f.crossings)
    crossings.push_back({{"u_stars", {c.u_star_a, c.u_star_b}}, {"z_d", c.z / d}, {"u", c.u}});
  // No crossing, no focal point: null, not a point at z = 0.
  const auto or_null = [&f](double v) { return f.crossings.empty() ? nlohmann::json() : nlohmann::json(v); };
  return {{"u_star", a.focal_ustars},
          {"runs", rows},
          {"z_focal_fit_d", f.fit_z / d},
          {"u_focal_fit", f.fit_u},
          {"fit_r2", f.fit_r2},
          {"z_focal_d", or_null(f.crossing_z / d)},
          {"u_focal", or_null(f.crossing_u)},
          {"crossing_z_range_d", {or_null(f.crossing_z_min / d), or_null(f.crossing_z_max / d)}},
          {"pairs", f.pairs},
          {"crossings", crossings},
          {"log_band_d", a.focal_band},
          {"focus_above_d", a.focal_above},
          {"diameter", d},
          {"duration", a.flux.duration},
          {"average_from", a.flux.average_from},
          {"splash", a.flux.splash},
          {"grainlab_version", GRAINLAB_VERSION}};
}

void write_focal_out(const std::string& out, const std::vector<WindProfile>& p, const FocalPoint& f,
                     const nlohmann::json& j, double d) {
  namespace fs = std::filesystem;
  const std::string tmp = out + ".partial";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  write_file_atomically(tmp + "/profiles.csv", profiles_csv(p, d));
  write_file_atomically(tmp + "/focal.json", j.dump(2));
  validation::write_plots(focal_plots(p, f, d), tmp);
  fs::remove_all(out);
  fs::rename(tmp, out);
}

}  // namespace

int hybrid_focal_command(const RipplesCommands& a) {
  check_focal_options(a);
  refuse_existing_out(a.out, a.force);
  ripples::hybrid::FluxOptions base = a.flux;
  validation::attach_recorded_splash(base);
  base.distributed = parallel::size() > 1;  // each run shared by the ranks, as in hybrid-flux
  std::vector<FluxResult> runs;
  std::vector<WindProfile> profiles;
  if (!a.hybrid_checkpoint.empty()) std::filesystem::create_directories(a.hybrid_checkpoint);
  for (double u : a.focal_ustars) {
    ripples::hybrid::FluxOptions o = base;
    o.u_star = u;
    if (!a.quiet && parallel::rank() == 0)
      fmt::print(stderr, "grainlab ripples hybrid-focal: flux run at u* = {} cm/s, {} t* averaged from {}\n",
                 u, o.duration, o.average_from);
    // With --checkpoint DIR, each u*'s run keeps its state in DIR/u<U>.h5 and continues from it (a
    // finished run's file ends at its last t*, so the run is not redone).
    std::string checkpoint, restart;
    if (!a.hybrid_checkpoint.empty()) {
      checkpoint = (std::filesystem::path(a.hybrid_checkpoint) / fmt::format("u{:g}.h5", u)).string();
      if (std::filesystem::exists(checkpoint)) restart = checkpoint;
    }
    ripples::hybrid::FluxOptions asked = a.flux;
    asked.u_star = u;
    try {
      runs.push_back(run_flux_checkpointed(o, asked, checkpoint, restart));
    } catch (const InputError& e) {
      if (e.key() != "--restart") throw;
      throw InputError(e.where(), "--checkpoint", e.message() + "; or give another --checkpoint folder");
    }
    if (runs.back().u_mean.empty())
      throw InputError({"--ustar", 0}, fmt::format("{}", u),
                       "the transport died before the averaging window");
    profiles.push_back({u, runs.back().z, runs.back().u_mean});
  }
  const double d = a.flux.diameter;
  const FocalPoint f =
      ripples::hybrid::focal_point(profiles, a.focal_band[0] * d, a.focal_band[1] * d, a.focal_above * d);
  const nlohmann::json j = focal_json(a, runs, profiles, f);
  if (parallel::rank() != 0) return 0;
  if (!a.out.empty()) write_focal_out(a.out, profiles, f, j, d);
  if (a.json) {
    fmt::print("{}\n", j.dump());
    return 0;
  }
  fmt::print("| u* (cm/s) | Q* | z0 (d) | log-layer spread of ln z0 |\n|---|---|---|---|\n");
  for (std::size_t k = 0; k < runs.size(); ++k)
    fmt::print("| {:g} | {:.5f} | {:.4g} | {:.2g} |\n", profiles[k].u_star, runs[k].mass_flux_star,
               f.log_layers[k].z0 / d, f.log_layers[k].spread);
  fmt::print("eq. 32 fit of ln z0 against 1/u*: z_F = {:.1f} d, u_F = {:.0f} cm/s (r^2 = {:.4f})\n",
             f.fit_z / d, f.fit_u, f.fit_r2);
  if (f.crossings.empty())
    fmt::print("no pair of the {} profiles crosses above {:g} d (--focus-above)\n", f.pairs, a.focal_above);
  else
    fmt::print(
        "profiles cross ({} of {} pairs) at z = {:.1f} d (range {:.1f}-{:.1f} d), u = {:.0f} cm/s "
        "(medians)\n",
        f.crossings.size(), f.pairs, f.crossing_z / d, f.crossing_z_min / d, f.crossing_z_max / d,
        f.crossing_u);
  if (!a.out.empty()) fmt::print("plots and profiles in {}/\n", a.out);
  return 0;
}

}  // namespace grainlab::cli
