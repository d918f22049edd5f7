// `grainlab ripples lattice --config F [--out F.h5] [--seeds N] [--json]`: the lattice-bed model (Fig. 5.21),
// h(x, t) and the surface statistics per frame; with --seeds, the final statistics over an ensemble.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "ensemble.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
#include "ripple_config.hpp"
#include "ripples_commands.hpp"
#include "splash_file.hpp"
#include "wind_model.hpp"

namespace grainlab::cli {

using namespace grainlab::ripples;

namespace {

struct LatticeOutcome {
  SampleTable h, history;
  LatticeSurfaceStats final;
  LatticeLengthScales scales;
  double impacts_per_second = 0;
};

LatticeOutcome run_lattice(const LatticeRun& run) {
  const LatticeParams& p = run.params;
  LatticeModel m(p);
  LatticeOutcome o{
      {"h", "surface layer index (a layer is d / 2) per column (columns) at each frame (rows)", {}, {}},
      {"history",
       "per frame: impacts per surface grain, rms (layers), wavelength (lattice spacings), crest "
       "height (layers), stoss and lee slopes (deg)",
       {"ejections_per_grain", "roughness", "wavelength", "height", "stoss_deg", "lee_deg"},
       {}},
      {},
      {},
      0};
  for (int i = 0; i < p.columns; ++i) o.h.columns.push_back(fmt::format("c{}", i));
  auto record = [&] {
    o.h.rows.emplace_back(m.heights().begin(), m.heights().end());
    const LatticeSurfaceStats s = lattice_surface_stats(m.heights());
    o.history.rows.push_back(
        {m.ejections_per_surface_grain(), s.rms, s.wavelength, s.height, s.stoss_deg, s.lee_deg});
    o.final = s;
  };
  record();
  const long total = std::lround(run.ejections_per_grain * p.columns / 2);
  const long chunk = std::max(1L, total / run.frames);
  const auto t0 = std::chrono::steady_clock::now();
  for (long done = 0; done < total; done += chunk) {
    m.fire(std::min(chunk, total - done));
    record();
  }
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.impacts_per_second = dt > 0 ? m.impacts() / dt : 0;
  o.scales = lattice_length_scales(m.heights());
  return o;
}

}  // namespace

// The lattice model's splash mode reads its hops through ejecta_hop_lengths or, in wind mode, through
// wind_blown_hops (saltation/): the Ch. IV wind's grains are the thesis's (d = 0.025 cm, 2.6 g/cm^3).
ripples::SplashHops splash_hops(const LatticeRun& run) {
  using namespace grainlab::saltation;
  const SplashFile f = run.splash == "sand-gun" ? sand_gun_splash() : read_splash_file(run.splash);
  ripples::SplashHops out;
  if (run.splash_wind > 0) {
    WindModelOptions o;
    o.u_star = run.splash_wind;
    WindBlownHops w;
    try {
      w = wind_blown_hops(f, o);
    } catch (const std::invalid_argument& e) {
      throw InputError({run.splash, 0}, "splash_wind", e.what());
    }
    if (parallel::rank() == 0)
      fmt::print(
          stderr,
          "grainlab ripples: the splash's steady wind at u* = {} cm/s (u*_eff {:.1f}): ejecting impacts "
          "at {:.1f} sqrt(g d), {:.1f} deg on average; {} recorded ejecta of {} cells flown: mean hop "
          "{:.1f} d (ballistic {:.1f} d), {:.0f} % upstream\n",
          o.u_star, w.wind.u_star_eff, w.impact_speed, w.impact_deg, w.ejecta_flown, w.cells_used,
          validation::mean_interval(w.hops_d).mean, w.ballistic_mean_d, 100 * w.upstream_share);
    out.wind_state = {{"u_star_eff", w.wind.u_star_eff},
                      {"impact_speed", w.impact_speed},
                      {"impact_angle", w.impact_deg},
                      {"upstream_share", w.upstream_share},
                      {"ballistic_mean_hop_d", w.ballistic_mean_d},
                      {"wind_mean_hop_d", validation::mean_interval(w.hops_d).mean},
                      {"ejecta_flown", static_cast<double>(w.ejecta_flown)},
                      {"cells_used", static_cast<double>(w.cells_used)}};
    out.hops_d = std::move(w.hops_d), out.impact_deg = w.impact_deg;
    return out;
  }
  out.hops_d = ejecta_hop_lengths(f, run.splash_angle, run.splash_speed);
  if (out.hops_d.empty())
    throw InputError({run.splash, 0}, "", "has no ejecta (or reptation lengths) in the cells chosen");
  return out;
}

namespace {

// One seed's final numbers, in the order stats_json names them.
std::vector<double> stats_row(const LatticeSurfaceStats& s, const LatticeLengthScales& l) {
  return {
      double(l.f_peak), l.autocorrelation_wavelength, s.wavelength, s.height, s.stoss_deg, s.lee_deg, s.rms};
}

nlohmann::json stats_json(const std::vector<double>& r) {
  return {{"f_peak", r[0]},     {"autocorrelation_wavelength", r[1]},
          {"wavelength", r[2]}, {"height", r[3]},
          {"stoss_deg", r[4]},  {"lee_deg", r[5]},
          {"roughness", r[6]}};
}

}  // namespace

namespace {

// The ensemble's mean, s.d. and 95 % half-width of each statistic over the members.
nlohmann::json ensemble_summary(const nlohmann::json& members) {
  nlohmann::json summary;
  for (const char* key : {"wavelength", "height", "stoss_deg", "lee_deg", "roughness", "f_peak",
                          "autocorrelation_wavelength"}) {
    std::vector<double> values;
    for (const auto& m : members) values.push_back(m[key].get<double>());
    const validation::MeanInterval mi = validation::mean_interval(values);
    // One seed has no spread: null, not an interval of zero width.
    const bool spread = values.size() > 1;
    summary[key] = {{"mean", mi.mean},
                    {"sd", spread ? nlohmann::json(mi.sd) : nlohmann::json()},
                    {"half_width_95", spread ? nlohmann::json(mi.half_width()) : nlohmann::json()}};
  }
  return summary;
}

void print_lattice_summary(const RipplesCommands& a, const LatticeRun& run, const LatticeOutcome& first,
                           const nlohmann::json& members, const nlohmann::json& summary) {
  const LatticeParams& p = run.params;
  if (p.hops_d.empty()) {
    fmt::print(
        "lattice-bed model: {} columns, impacts at {} deg, hops {} forward / {} backward, brink share {}\n",
        p.columns, p.impact_deg, p.forward, p.backward, p.brink_probability);
  } else {
    fmt::print(
        "lattice-bed model: {} columns, impacts at {:.1f} deg, hops drawn from {} ({} lengths, mean {:.1f} "
        "d{}), "
        "brink share {}\n",
        p.columns, p.impact_deg, run.splash, p.hops_d.size(), validation::mean_interval(p.hops_d).mean,
        run.splash_wind > 0 ? fmt::format(", flown in the wind at u* = {} cm/s", run.splash_wind) : "",
        p.brink_probability);
  }
  for (std::size_t k = 0; k < first.history.rows.size();
       k += std::max<std::size_t>(1, first.history.rows.size() / 10)) {
    const auto& r = first.history.rows[k];
    fmt::print(
        "  {:6.1f} ejections per grain: wavelength {:6.1f}, height {:5.1f} layers, stoss {:4.1f}, lee "
        "{:4.1f} deg\n",
        r[0], r[2], r[3], r[4], r[5]);
  }
  for (const char* key :
       {"wavelength", "height", "stoss_deg", "lee_deg", "f_peak", "autocorrelation_wavelength"}) {
    if (members.size() > 1)
      fmt::print("  final {} over {} seeds: {:.2f} +- {:.2f} (95 %)\n", key, members.size(),
                 summary[key]["mean"].get<double>(), summary[key]["half_width_95"].get<double>());
    else
      fmt::print("  final {}: {:.2f} (one seed: --seeds N gives an interval)\n", key,
                 summary[key]["mean"].get<double>());
  }
  fmt::print("  {:.3g} impacts per second (with the per-frame statistics)\n", first.impacts_per_second);
  if (!a.out.empty()) fmt::print("wrote {} (h(x, t): {} frames)\n", a.out, first.h.rows.size());
}

}  // namespace

int lattice_command(const RipplesCommands& a) {
  refuse_existing_out(a.out, a.force);
  LatticeRun run = read_lattice_config(a.config);
  ripples::SplashHops hops;
  if (!run.splash.empty()) {
    hops = splash_hops(run);
    apply_splash_hops(run, hops);
  }
  if (a.lattice_ejections > 0) run.ejections_per_grain = a.lattice_ejections;
  // The first seed's run (its h(x, t) for --out, its speed) is rank 0's alone: the other ranks take the
  // other seeds of the ensemble instead of running it too.
  const bool root = parallel::rank() == 0;
  const LatticeOutcome first = root ? run_lattice(run) : LatticeOutcome{};
  if (!a.out.empty() && root)
    write_sample_tables(a.out, {first.h, first.history},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", "the thesis's lattice-bed model (Ch. V, Fig. 5.21)"},
                         {"config", run.text},
                         {"units",
                          "heights in layers (d / 2), x in columns (sqrt(3) d / 2), wavelength in "
                          "lattice spacings (sqrt(3) d)"}});
  if (!a.out.empty() && root) write_spacetime_plot(a.out, a.force, a.json);
  // The ensemble: the same config with seeds seed, seed + 1, ...; under mpirun the seeds are dealt out
  // over the ranks and gathered, so the numbers are the same on any rank count.
  const std::uint64_t seed0 = run.params.seed;
  const auto table = validation::run_ensemble(static_cast<std::size_t>(a.lattice_seeds), 7,
                                              [&](std::size_t k) -> std::vector<double> {
                                                if (k == 0) return stats_row(first.final, first.scales);
                                                LatticeRun member = run;
                                                member.params.seed = seed0 + k;
                                                const LatticeOutcome o = run_lattice(member);
                                                return stats_row(o.final, o.scales);
                                              });
  nlohmann::json members = nlohmann::json::array();
  for (const auto& row : table) members.push_back(stats_json(row));
  if (!root) return 0;
  const nlohmann::json summary = ensemble_summary(members);
  if (!a.json) {
    print_lattice_summary(a, run, first, members, summary);
    return 0;
  }
  fmt::print("{}\n", nlohmann::json{{"seeds", members.size()},
                                    {"ejections_per_grain", run.ejections_per_grain},
                                    {"impacts_per_second", first.impacts_per_second},
                                    {"impact_angle", run.params.impact_deg},
                                    {"mean_hop_d", run.params.hops_d.empty()
                                                       ? 0.0
                                                       : validation::mean_interval(run.params.hops_d).mean},
                                    {"splash_wind", run.splash_wind},
                                    {"splash_wind_state", hops.wind_state},
                                    {"final", summary},
                                    {"members", members}}
                         .dump(2));
  return 0;
}

}  // namespace grainlab::cli
