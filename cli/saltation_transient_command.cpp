// `grainlab saltation transient`: the thesis's time-dependent saltation (eq. 4.35) from a seed of launches,
// through saturation and any changes of u*, beside the steady state of the same splash and wind
// (docs/saltation.md, "Saltation in time").
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "option_scope.hpp"
#include "report.hpp"
#include "saltation_commands.hpp"
#include "transient.hpp"
#include "transient_checkpoint.hpp"

namespace grainlab::cli {

namespace fs = std::filesystem;
using namespace grainlab::saltation;

namespace {

std::string transient_csv(const TransientResult& r) {
  std::string csv =
      "t_s,u_star_cm_s,launch_rate_per_cm2_s,airborne_per_cm2,mass_flux_g_cm_s,u_star_eff_cm_s\n";
  for (const TransientSample& s : r.samples)
    csv += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", s.t, s.u_star, s.launch_rate,
                       s.airborne, s.mass_flux, s.u_star_eff);
  return csv;
}

std::vector<validation::PlotSpec> transient_plots(const TransientResult& r, const WindModelResult& steady) {
  using validation::PlotSpec;
  PlotSpec q{"transient_flux.png",
             "Mass flux in time (dashed: the steady state)",
             "t (s)",
             "Q (g/(cm s))",
             false,
             {}};
  PlotSpec u{"transient_ustar_eff.png",
             "u*_eff in time (dashed: the steady state)",
             "t (s)",
             "u*_eff (cm/s)",
             false,
             {}};
  PlotSpec::Series qs{"grainlab, eq. 4.35", "line", {}, {}, {}}, us{"grainlab, eq. 4.35", "line", {}, {}, {}};
  for (const TransientSample& s : r.samples)
    qs.x.push_back(s.t), qs.y.push_back(s.mass_flux), us.x.push_back(s.t), us.y.push_back(s.u_star_eff);
  q.series.push_back(qs), u.series.push_back(us);
  if (steady.failure.empty() && !r.samples.empty()) {
    const double t0 = r.samples.front().t, t1 = r.samples.back().t;
    q.series.push_back(
        {"steady state (Fig. 4.10)", "dashed", {t0, t1}, {steady.mass_flux, steady.mass_flux}, {}});
    u.series.push_back(
        {"steady state (Fig. 4.10)", "dashed", {t0, t1}, {steady.u_star_eff, steady.u_star_eff}, {}});
  }
  return {q, u};
}

// The run's options from the command line, refusing what cannot run (an output folder in use, --case with
// --splash, --change values out of order or range).
TransientOptions transient_options(const SaltationCommands& a) {
  if (!a.transient_out.empty() && fs::exists(a.transient_out) && !fs::is_empty(a.transient_out) && !a.force)
    throw InputError({"--out", 0}, a.transient_out,
                     "exists and is not empty; pass --force to replace its files");
  if (!a.transient_splash.empty())
    refuse_if_given(a.transient->get_option("--case"), "give either --case or --splash FILE, not both");
  check_stop_at(a.transient_stop_at, a.transient_checkpoint, a.transient_duration,
                fmt::format("--duration {}", a.transient_duration));
  if (a.transient_changes.size() % 2 != 0)
    throw InputError({"--change", 0}, "", "give pairs of a time (s) and a new u* (cm/s)");
  TransientOptions o;
  o.model.u_star = a.transient_ustar;
  o.model.grain.radius =
      case_grain_diameter(a.transient_case, a.transient_diameter_option, a.grain_diameter) / 2;
  o.dt = a.transient_dt, o.duration = a.transient_duration;
  o.record_every = std::max(1, static_cast<int>(std::lround(a.transient_record / a.transient_dt)));
  double last = 0;
  for (std::size_t i = 0; i < a.transient_changes.size(); i += 2) {
    const double t = a.transient_changes[i], u = a.transient_changes[i + 1];
    if (!(t > last && t < a.transient_duration))
      throw InputError({"--change", 0}, fmt::format("{}", t),
                       "change times must increase and lie inside the run (0, --duration)");
    if (!(u > 0 && u < 1000))
      throw InputError({"--change", 0}, fmt::format("{}", u), "u* must lie in (0, 1000) cm/s");
    o.ustar_changes.push_back({t, u}), last = t;
  }
  return o;
}

// Advances `state` to the run's end or --stop-at in pieces of 100 steps, saving it whenever
// --checkpoint-every seconds of wall time have passed, and at the end.
void advance_to_stop(const SaltationCommands& a, const TransientOptions& o, const SplashKernel& splash,
                     TransientState& state, const std::string& fingerprint) {
  const long last_step = transient_last_step(o);
  const long stop =
      a.transient_stop_at > 0 ? std::min(last_step, std::lround(a.transient_stop_at / o.dt)) : last_step;
  auto saved = std::chrono::steady_clock::now();
  while (!state.over && state.next_step <= stop) {
    advance_transient(o, splash, state, std::min(stop, state.next_step + 99));
    const auto now = std::chrono::steady_clock::now();
    if (!a.transient_checkpoint.empty() &&
        std::chrono::duration<double>(now - saved).count() >= a.transient_checkpoint_every) {
      write_transient_checkpoint(a.transient_checkpoint, state, fingerprint);
      saved = now;
    }
  }
  if (!a.transient_checkpoint.empty()) write_transient_checkpoint(a.transient_checkpoint, state, fingerprint);
}

nlohmann::json transient_json(const SaltationCommands& a, const TransientOptions& o, const TransientResult& r,
                              const WindModelResult& steady) {
  return {{"grainlab_version", GRAINLAB_VERSION},
          {"case", a.transient_case},
          {"splash", a.transient_splash},
          {"u_star", a.transient_ustar},
          {"changes", a.transient_changes},
          {"dt", o.dt},
          {"duration", o.duration},
          {"died", r.died},
          {"failure", r.failure},
          {"settling_time", r.settling_time},
          {"final_mass_flux", r.final_mass_flux},
          {"final_u_star_eff", r.final_u_star_eff},
          {"final_growth_rate", r.final_growth_rate},
          {"steady", steady.failure.empty()
                         ? nlohmann::json{{"mass_flux", steady.mass_flux}, {"u_star_eff", steady.u_star_eff}}
                         : nlohmann::json{{"failure", steady.failure}}},
          {"wall_seconds", r.wall_seconds}};
}

void print_transient_summary(const SaltationCommands& a, const TransientOptions& o, const TransientResult& r,
                             const WindModelResult& steady) {
  fmt::print("time-dependent saltation (eq. 4.35), {}, u* = {} cm/s, dt {} s, {} s ({:.1f} s of wall time)\n",
             case_label(a.transient_case, a.transient_splash), a.transient_ustar, o.dt, o.duration,
             r.wall_seconds);
  if (r.died || !r.failure.empty()) fmt::print("  {}\n", r.failure);
  fmt::print("  over the last fifth: Q {:.4g} g/(cm s), u*_eff {:.2f} cm/s; steady state: ",
             r.final_mass_flux, r.final_u_star_eff);
  if (steady.failure.empty())
    fmt::print("Q {:.4g}, u*_eff {:.2f}\n", steady.mass_flux, steady.u_star_eff);
  else
    fmt::print("none ({})\n", steady.failure);
  if (r.settling_time >= 0)
    fmt::print("  the flux settles within 5 % {:.2f} s after the last change\n", r.settling_time);
  else {
    fmt::print("  the flux has not settled within 5 % by the end: the grains in the air {} at {:.3g} per s\n",
               r.final_growth_rate >= 0 ? "grow" : "decay", std::abs(r.final_growth_rate));
    // Still growing toward a steady state it has not reached: how much longer at this rate (near threshold
    // the growth is slow, and the default duration is too short).
    if (steady.failure.empty() && r.final_growth_rate > 0 && r.final_mass_flux > 0 &&
        r.final_mass_flux < steady.mass_flux) {
      const double more = std::log(steady.mass_flux / r.final_mass_flux) / r.final_growth_rate;
      fmt::print("  at that rate it reaches the steady flux about {:.1f} s later: try --duration {:.0f}\n",
                 more, std::ceil(o.duration + 2 * more));
    }
  }
  if (!a.transient_out.empty()) fmt::print("wrote {}/transient.csv and its plots\n", a.transient_out);
}

}  // namespace

int transient_command(const SaltationCommands& a) {
  const TransientOptions o = transient_options(a);
  const SplashKernel splash = case_splash(a.transient_case, a.transient_splash, o.model, 1.0);
  // Everything that fixes what the run computes: a checkpoint from other options would continue another run.
  const std::string fingerprint = fmt::format(
      "case {}\nsplash {}\nu_star {:.17g}\nchanges {}\ndt {:.17g}\nduration {:.17g}\nrecord_every {}\n"
      "grain_diameter {:.17g}\n",
      a.transient_case, a.transient_splash, a.transient_ustar, nlohmann::json(a.transient_changes).dump(),
      o.dt, o.duration, o.record_every, 2 * o.model.grain.radius);  // (halving and doubling are exact)
  const auto wall0 = std::chrono::steady_clock::now();
  TransientState state = a.transient_restart.empty()
                             ? start_transient(o)
                             : read_transient_checkpoint(a.transient_restart, o, fingerprint);
  advance_to_stop(a, o, splash, state, fingerprint);
  if (!state.over) {
    fmt::print(stderr, "stopped at t = {:.6g} s; continue with --restart {}\n",
               static_cast<double>(state.next_step) * o.dt, a.transient_checkpoint);
    return 0;
  }
  TransientResult r = finish_transient(state);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  // The steady state the run should approach, at the last u*.
  WindModelOptions steady_options = o.model;
  if (!o.ustar_changes.empty()) steady_options.u_star = o.ustar_changes.back().second;
  const WindModelResult steady = solve_wind_model(steady_options, splash);
  const nlohmann::json out = transient_json(a, o, r, steady);
  if (!a.transient_out.empty()) {
    fs::create_directories(a.transient_out);
    write_file_atomically((fs::path(a.transient_out) / "transient.csv").string(), transient_csv(r));
    write_file_atomically((fs::path(a.transient_out) / "transient.json").string(), out.dump(2));
    validation::write_plots(transient_plots(r, steady), a.transient_out);
  }
  if (a.transient_json)
    fmt::print("{}\n", out.dump(2));
  else
    print_transient_summary(a, o, r, steady);
  return 0;
}

}  // namespace grainlab::cli
