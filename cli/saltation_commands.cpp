#include "saltation_commands.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "conveyor.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"
#include "number_ranges.hpp"
#include "option_scope.hpp"
#include "output_path.hpp"
#include "plot_beside.hpp"
#include "saltation_heights.hpp"
#include "study.hpp"
#include "wind_model.hpp"

namespace grainlab::cli {

namespace {

using namespace grainlab::saltation;

// An option given to the conveyor's other kind of case would change nothing.
void refuse_given(const std::vector<CLI::Option*>& options, const std::string& why) {
  for (const CLI::Option* o : options) refuse_if_given(o, why);
}

int map_case(const SaltationCommands& a) {
  ConveyorMapParams p = table_4_2(a.case_name);
  p.order = a.order;
  refuse_given(a.distribution_options, "is for CASES A, B and C (the distribution splash)");
  const ConveyorMapResult r = conveyor_map(p, a.F0, a.v_oy0, a.max_iterations);
  const MapState& s = r.history.back();
  const DeltaSteadyState closed = conveyor_delta_steady(p.f_at(p.v_g), p.eps, p.v_g, p.P_T, p.zeta);
  // Linearise at the steady state of eqs 4.3-4.5 (where the map ends when it converges).
  MapState fixed = s;
  if (closed.transport) fixed.F = closed.F, fixed.v_oy = closed.v_boy, fixed.v_c = closed.v_c;
  const ConveyorLinearization L = conveyor_linearization(p, fixed);
  const MapState& prev = r.history[r.history.size() - 2];
  if (a.json) {
    nlohmann::json j{{"case", a.case_name},
                     {"F", s.F},
                     {"v_oy", s.v_oy},
                     {"v_c", s.v_c},
                     {"iterations", r.iterations},
                     {"converged", r.converged},
                     {"order", p.order},
                     {"eigenvalues",
                      {{L.eigenvalues[0].real(), L.eigenvalues[0].imag()},
                       {L.eigenvalues[1].real(), L.eigenvalues[1].imag()}}},
                     {"closed_form", {{"F", closed.F}, {"v_oy", closed.v_boy}, {"v_c", closed.v_c}}}};
    if (!r.converged) j["last_two"] = {{prev.F, prev.v_oy, prev.v_c}, {s.F, s.v_oy, s.v_c}};
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("conveyor-belt map (eq. 4.23), CASE {} of Table 4.2, order {}, from F = {}, v_oy = {}\n",
             a.case_name, p.order, a.F0, a.v_oy0);
  fmt::print("  {} after {} iterations: F {:.6g}, v_oy {:.6g}, v_c {:.6g}\n",
             r.converged ? "converged" : "NOT converged", r.iterations, s.F, s.v_oy, s.v_c);
  if (!r.converged)
    fmt::print(
        "  the last two states: ({:.5g}, {:.5g}, {:.5g}) and ({:.5g}, {:.5g}, {:.5g}): an oscillation\n",
        prev.F, prev.v_oy, prev.v_c, s.F, s.v_oy, s.v_c);
  fmt::print("  closed form (eqs 4.3-4.5) at f(v_g) = {}: F {:.6g}, v_oy {:.6g}, v_c {:.6g}\n", p.f_at(p.v_g),
             closed.F, closed.v_boy, closed.v_c);
  fmt::print(
      "  one-step Jacobian eigenvalues there (|lambda| > 1: the steady state repels): {:.4g}{:+.4g}i, "
      "{:.4g}{:+.4g}i\n",
      L.eigenvalues[0].real(), L.eigenvalues[0].imag(), L.eigenvalues[1].real(), L.eigenvalues[1].imag());
  return 0;
}

int distribution_case(const SaltationCommands& a) {
  refuse_given(a.map_options, "is for CASES D and E (the time map of eq. 4.23)");
  const DistributionSplashParams p = table_4_1(a.case_name);
  // The default start is flat over the grid; --start-below puts the same number of grains in the bins
  // below it only (the spec's narrow start, which kills the flux in CASES A and B).
  std::vector<double> start;
  if (a.start_below > 0) {
    const std::size_t below = static_cast<std::size_t>(std::ceil(a.start_below / p.dmu - 0.5));
    if (below == 0 || below > static_cast<std::size_t>(p.bins))
      throw InputError(
          {"--start-below", 0}, fmt::format("{}", a.start_below),
          fmt::format("must leave at least one bin centre below it, within the grid's {} bins of {}", p.bins,
                      p.dmu));
    start.assign(static_cast<std::size_t>(p.bins), 0.0);
    for (std::size_t i = 0; i < below; ++i) start[i] = double(p.bins) / double(below);
  }
  const DistributionResult r = conveyor_distribution(p, a.max_iterations, 1e-10, start);
  if (!r.failure.empty()) fmt::print(stderr, "grainlab saltation conveyor: {}\n", r.failure);
  if (a.json) {
    nlohmann::json j{{"case", a.case_name},      {"v_c", r.v_c}, {"iterations", r.iterations},
                     {"converged", r.converged}, {"mu", r.mu},   {"F", r.F},
                     {"residuals", r.residuals}};
    if (!r.failure.empty()) j["failure"] = r.failure;
    fmt::print("{}\n", j.dump(2));
    return r.converged ? 0 : 1;
  }
  fmt::print("conveyor-belt model with the distribution splash (eqs 4.12-4.16), CASE {} of Table 4.1\n",
             a.case_name);
  fmt::print("  {} after {} iterations: v_c = {:.5g}\n", r.converged ? "converged" : "NOT converged",
             r.iterations, r.v_c);
  if (!r.converged) return 1;
  double peak = 0;
  for (double x : r.F) peak = std::max(peak, x);
  for (std::size_t i = 0; i < r.mu.size(); ++i)
    fmt::print("  mu {:6.3f}  F {:10.4g}  {}\n", r.mu[i], r.F[i],
               std::string(static_cast<std::size_t>(40 * r.F[i] / std::max(peak, 1e-300)), '#'));
  return 0;
}

// Every profile and distribution of a run, as named tables (docs/saltation.md lists them).
void write_wind_run(const std::string& path, const SaltationCommands& a, const WindModelOptions& o,
                    const WindModelResult& r) {
  SampleTable wind{
      "wind",
      "per height y (cm): wind u with grains and u_clean without (cm/s), fluid stress tau "
      "(dyn/cm^2), drag the grains take from the air (dyn/cm^3), number density (1/cm^3), "
      "horizontal number flux (1/(cm^2 s)), kinetic-energy flux N m v_x^2 / 2 (erg/cm^3), and the drag "
      "resolved by 16 flights per launch bin (dyn/cm^3)",
      {"y", "u", "u_clean", "tau", "drag", "number_density", "number_flux", "energy_flux", "drag_resolved"},
      {}};
  for (std::size_t k = 0; k < r.y.size(); ++k)
    wind.rows.push_back({r.y[k], r.u[k], r.u_clean[k], r.tau[k], r.drag[k], r.number_density[k],
                         r.number_flux[k], r.energy_flux[k], r.drag_resolved[k]});
  SampleTable launch{"launch",
                     "per launch bin: v_oy (cm/s), F (grains per cm^2 per s per cm/s), v_ox, the landing "
                     "velocity, hop height and length (cm), flight time (s)",
                     {"v_oy", "F", "v_ox", "v_ix", "v_iy", "hop_height", "hop_length", "flight_time"},
                     {}};
  for (std::size_t j = 0; j < r.F.size(); ++j) {
    const Trajectory& t = r.trajectories[j];
    launch.rows.push_back({r.v_launch[j], r.F[j], r.v_ox[j], t.v_ix, t.v_iy, t.height, t.length, t.time});
  }
  SampleTable conv{
      "convergence", "largest relative change of F or u per iteration", {"iteration", "residual"}, {}};
  for (std::size_t n = 0; n < r.residuals.size(); ++n) conv.rows.push_back({double(n + 1), r.residuals[n]});
  std::map<std::string, std::string> meta = {{"grainlab_version", GRAINLAB_VERSION},
                                             {"model", "thesis Ch. IV steady-state saltation (Fig. 4.10)"},
                                             {"splash", case_label(a.wind_case, a.splash_file)},
                                             {"units", "cgs: cm, g, s"},
                                             {"u_star", fmt::format("{}", o.u_star)},
                                             {"u_star_eff", fmt::format("{:.17g}", r.u_star_eff)},
                                             {"mass_flux", fmt::format("{:.17g}", r.mass_flux)},
                                             {"grain_diameter", fmt::format("{}", 2 * o.grain.radius)},
                                             {"reynolds_factor", fmt::format("{}", o.reynolds_factor)},
                                             {"drag_smoothing_cm", fmt::format("{}", o.drag_smoothing)},
                                             {"launch_min", fmt::format("{}", o.launch_min)},
                                             {"launch_dv", fmt::format("{}", o.dv)},
                                             {"ejecta_below_range", a.ejecta_below},
                                             {"converged", r.converged ? "true" : "false"},
                                             {"iterations", std::to_string(r.iterations)}};
  write_sample_tables(path, {wind, launch, conv}, meta);
}

int wind_command(const SaltationCommands& a) {
  if (!a.out.empty() && !a.force && std::filesystem::exists(a.out))
    throw InputError({"--out", 0}, a.out, "exists; pass --force to overwrite it");
  if ((a.wind_case == 0) == a.splash_file.empty())
    throw InputError({"--case", 0}, std::to_string(a.wind_case), "give either --case 1..7 or --splash FILE");
  const double diameter = case_grain_diameter(a.wind_case, a.wind_diameter_option, a.grain_diameter);
  WindModelOptions o;
  o.u_star = a.u_star, o.tolerance = a.tolerance;
  o.trajectory_tolerance = a.trajectory_tolerance, o.sample_interval = a.sample_interval;
  o.grain.radius = diameter / 2;
  o.reynolds_factor = a.reynolds_factor;
  o.flux_damping = a.flux_damping;
  o.drag_smoothing = a.drag_smoothing;
  o.launch_min = a.launch_min;
  o.ejecta_below_range = a.ejecta_below == "proportional" ? WindModelOptions::EjectaBelowRange::proportional
                                                          : WindModelOptions::EjectaBelowRange::line;
  // Another planet or gas: a preset, then any of g, air density and viscosity; buoyancy on. The analytic
  // splash is scaled by sqrt(g d) as in `saltation study` (a splash file is scaled by its own units).
  double splash_scale = 1;
  o.dv = a.launch_dv;
  o.profile_subdivisions = a.profile_flights;
  if (!a.planet.empty() || a.gravity > 0 || a.air_density > 0 || a.viscosity > 0) {
    Planet p = planet_preset(a.planet.empty() ? "earth" : a.planet);
    if (a.gravity > 0) p.g = a.gravity;
    if (a.air_density > 0) p.air_density = a.air_density;
    if (a.viscosity > 0) p.viscosity = a.viscosity;
    if (!(p.air_density < a.grain_density_wind))
      throw InputError({"--air-density", 0}, fmt::format("{}", p.air_density),
                       "must be below the grain density");
    o.g = p.g, o.fluid.density = p.air_density, o.fluid.viscosity = p.viscosity, o.buoyancy = true;
    splash_scale = std::sqrt(p.g * diameter / (981 * 0.025));
    o.dv *= splash_scale;
  }
  o.grain.density = a.grain_density_wind;
  o.bins = a.launch_bins;
  if (a.vx_bins == 0)
    refuse_if_given(a.wind->get_option("--vx-min"), "is for the 2-D launch grid of --vx-bins (not given)");
  o.vx_bins = a.vx_bins, o.vx_min = a.vx_min;
  const SplashKernel splash = case_splash(a.wind_case, a.splash_file, o, splash_scale);
  const WindModelResult r = solve_wind_model(o, splash);
  if (!r.failure.empty()) {
    fmt::print(stderr, "grainlab saltation wind: no steady state after {} iterations: {}\n", r.iterations,
               r.failure);
    if (a.wind_json)
      fmt::print(
          "{}\n",
          nlohmann::json{{"converged", false}, {"failure", r.failure}, {"iterations", r.iterations}}.dump(2));
    return 1;
  }
  const double tau_g_check = o.fluid.density * (a.u_star * a.u_star - r.u_star_eff * r.u_star_eff);
  if (!a.out.empty()) {
    write_wind_run(a.out, a, o, r);
    draw_plot_beside(a.out, "", "plot_saltation.py", {a.out, "--out"}, a.force, a.wind_json,
                     "wind profiles, launch distribution, drag and convergence");
  }
  if (a.wind_json) {
    const double d = 2 * o.grain.radius;  // peak heights from one grain diameter up, as Table 4.4's
    fmt::print(
        "{}\n",
        nlohmann::json{
            {"case", a.wind_case},
            {"splash", a.splash_file},
            {"ejecta_below_range", a.ejecta_below},
            {"grain_diameter", diameter},
            {"u_star", a.u_star},
            {"u_star_eff", r.u_star_eff},
            {"mass_flux", r.mass_flux},
            {"launch_rate", r.launch_rate},
            {"grain_stress", r.grain_stress},
            {"iterations", r.iterations},
            {"converged", r.converged},
            {"mean_hop_height", r.mean_hop_height},
            {"mean_hop_length", r.mean_hop_length},
            {"airborne_hop_height", r.airborne_hop_height},
            {"airborne_hop_length", r.airborne_hop_length},
            {"impact_velocity", {r.mean_impact_vx, r.mean_impact_vy}},
            {"spreads",  // standard deviations over the hops
             {{"hop_height", r.sd_hop_height},
              {"hop_length", r.sd_hop_length},
              {"impact_velocity", {r.sd_impact_vx, r.sd_impact_vy}}}},
            {"launch_vy",
             {{"mean", r.launch_vy.mean}, {"sd", r.launch_vy.sd}, {"half_width", r.launch_vy.half_width}}},
            {"peak_heights",
             {{"number_density", peak_height(r.y, r.number_density, d)},
              {"number_flux", peak_height(r.y, r.number_flux, d)},
              {"energy_flux", peak_height(r.y, r.energy_flux, d)},
              {"drag", peak_height(r.y, r.drag_resolved, d)}}},
            {"wall_seconds", r.wall_seconds},
            {"mean_flight_steps", r.flights > 0 ? double(r.flight_steps) / double(r.flights) : 0.0},
            {"residuals", r.residuals}}
            .dump(2));
    return 0;
  }
  fmt::print("steady-state saltation (thesis Ch. IV, Fig. 4.10), splash {}, grains d = {} cm, u* = {} cm/s\n",
             case_label(a.wind_case, a.splash_file), diameter, a.u_star);
  fmt::print("  {} after {} iterations ({} wind-trajectory passes, {:.2f} s)\n",
             r.converged ? "converged" : "NOT converged", r.iterations, r.trajectory_passes, r.wall_seconds);
  fmt::print("  u*_eff {:.2f} cm/s; grain-borne stress {:.4g} dyn/cm^2 (rho (u*^2 - u*_eff^2) = {:.4g})\n",
             r.u_star_eff, r.grain_stress, tau_g_check);
  fmt::print("  mass flux {:.4g} g/(cm s); {:.4g} launches per cm^2 per s\n", r.mass_flux, r.launch_rate);
  fmt::print("  mean hop height {:.2f} cm, length {:.1f} cm; mean impact velocity ({:.0f}, {:.0f}) cm/s\n",
             r.mean_hop_height, r.mean_hop_length, r.mean_impact_vx, r.mean_impact_vy);
  fmt::print(
      "  their s.d. over the hops: height {:.2f} cm, length {:.1f} cm, impact velocity ({:.0f}, {:.0f}) "
      "cm/s\n",
      r.sd_hop_height, r.sd_hop_length, r.sd_impact_vx, r.sd_impact_vy);
  fmt::print("  over the grains in the air at an instant: hop height {:.2f} cm, length {:.1f} cm\n",
             r.airborne_hop_height, r.airborne_hop_length);
  fmt::print("  launch v_oy: mean {:.1f} cm/s, s.d. {:.1f}, half width at half maximum {:.1f}\n",
             r.launch_vy.mean, r.launch_vy.sd, r.launch_vy.half_width);
  fmt::print("  wind with grains (clean) at 0.1, 1, 10 cm: ");
  for (double h : {0.1, 1.0, 10.0})
    fmt::print("{:.0f} ({:.0f})  ", wind_at(o, r.y, r.u, h), wind_at(o, r.y, r.u_clean, h));
  fmt::print("cm/s\n");
  return 0;
}

}  // namespace

void SaltationCommands::add(CLI::App& app) {
  group = app.add_subcommand("saltation", "the thesis's saltation models (Ch. IV)");
  group->require_subcommand(1);
  add_conveyor();
  add_wind();
  add_study();
  add_dem();
  add_heights();
  add_transient();
}

void SaltationCommands::add_conveyor() {
  conveyor =
      group->add_subcommand("conveyor", "the conveyor-belt feedback model: Table 4.1 A-C and Table 4.2 D-E");
  conveyor->add_option("--case", case_name, "A, B, C (distribution splash) or D, E (delta splash, time map)")
      ->required()
      ->check(CLI::IsMember({"A", "B", "C", "D", "E"}));
  map_options = {
      conveyor->add_option("--order", order, "D, E: update order of eq. 4.23")
          ->default_val("simultaneous")
          ->check(CLI::IsMember({"simultaneous", "velocity-first"})),
      conveyor->add_option("--F0", F0, "D, E: starting flux")->default_val(50)->check(cli::positive()),
      conveyor->add_option("--v-oy0", v_oy0, "D, E: starting launch velocity")
          ->default_val(3)
          ->check(cli::positive())};
  distribution_options.push_back(
      conveyor
          ->add_option("--start-below", start_below,
                       "A, B, C: start with every grain launched below this mu (default: flat over the grid)")
          ->check(cli::positive()));
  conveyor->add_option("--max-iterations", max_iterations, "iteration limit")
      ->default_val(10000)
      ->check(cli::in_range(1, 10000000));
  conveyor->add_flag("--json", json, "print the final state as JSON");
}

void SaltationCommands::add_wind() {
  wind = group->add_subcommand(
      "wind",
      "steady-state saltation in a wind with grain feedback (Table 4.3 CASES 1-6, the sand gun's CASE 7)");
  wind->add_option("--case", wind_case,
                   "splash function: CASE 1-6 of Table 4.3, or 7: the sand gun's (Tables 3.11-3.12, "
                   "grains 0.078 cm unless --grain-diameter says otherwise)")
      ->check(cli::in_range(1, kSandGunCase));
  wind->add_option("--splash", splash_file,
                   "or a grainlab-splash/1 file (grainlab splash), scaled by sqrt(g d)")
      ->check(CLI::ExistingFile);
  wind_diameter_option =
      wind->add_option("--grain-diameter", grain_diameter,
                       "saltating grain diameter, cm (Ch. IV: 0.025; CASE 7: the sand gun's 0.078)")
          ->default_val(0.025)
          ->check(cli::in_range(0.0, 1.0, Ends::open));
  wind->add_option("--planet", planet,
                   "earth, mars or venus: g, gas density and viscosity (docs/saltation.md)")
      ->check(CLI::IsMember({"earth", "mars", "venus"}));
  wind->add_option("--g", gravity, "gravity, cm/s^2 (replaces the planet's)")->check(cli::in_range(1.0, 1e5));
  wind->add_option("--air-density", air_density, "gas density, g/cm^3 (replaces the planet's)")
      ->check(cli::in_range(1e-9, 10.0));
  wind->add_option("--viscosity", viscosity, "kinematic viscosity, cm^2/s (replaces the planet's)")
      ->check(cli::in_range(1e-9, 1e6));
  wind->add_option("--grain-density", grain_density_wind, "grain density, g/cm^3")
      ->default_val(2.6)
      ->check(cli::in_range(0.1, 30.0));
  wind->add_option(
          "--dv", launch_dv,
          "launch-velocity bin width, cm/s (the thesis does not give its own; scaled with the planet)")
      ->default_val(5)
      ->check(cli::in_range(0.0, 200.0, Ends::open_low));
  wind->add_option(
          "--profile-flights", profile_flights,
          "flights per launch bin, spread across it, for the height profiles (1: one at the bin's "
          "centre, as the thesis computed them; the wind and the steady state use one per bin either way)")
      ->default_val(16)
      ->check(cli::in_range(1, 256));
  wind->add_option("--bins", launch_bins, "launch-velocity bins (with --dv 5: up to 400 cm/s)")
      ->default_val(80)
      ->check(cli::in_range(8, 2000));
  wind->add_option("--vx-bins", vx_bins,
                   "a 2-D launch grid with this many v_ox values (0: the thesis's 1-D grid)")
      ->default_val(0)
      ->check(cli::in_range(0, 2000));
  wind->add_option("--vx-min", vx_min, "2-D grid: the lowest v_ox, cm/s (steps of the v_oy bin)")
      ->default_val(-100);
  wind->add_option("--out,-o", out, "write the profiles and distributions to this HDF5 file")
      ->check(cli::output_file());
  wind->add_flag("--force", force, "overwrite --out");
  wind->add_option("--re-factor", reynolds_factor,
                   "multiplies Re in eq. 4.31 (2: the diameter in place of r)")
      ->default_val(1)
      ->check(cli::in_range(0.0, 10.0, Ends::open_low));
  wind->add_option("--drag-smoothing", drag_smoothing,
                   "spread each height's grain drag over this many cm before the wind sees it (the thesis "
                   "averaged it over the spacing of trajectory heights; 0: as taken)")
      ->default_val(0)
      ->check(cli::in_range(0.0, 100.0));
  wind->add_option(
          "--launch-min", launch_min,
          "launches slower than this (cm/s, vertical) stay in the bed (0: every bin of eq. 4.34 fills; "
          "a reading test, docs/saltation.md \"Slow launches\")")
      ->default_val(0)
      ->check(cli::in_range(0.0, 1000.0, Ends::open_high));
  wind->add_option("--ejecta-below", ejecta_below,
                   "a splash file with moments only (the sand gun): ejecta per impact below its slowest "
                   "impacts, `line` (its least-squares line, zero below the root) or `proportional` (in "
                   "proportion to the impact speed)")
      ->default_val("line")
      ->check(CLI::IsMember({"line", "proportional"}));
  wind->add_option("--flux-damping", flux_damping,
                   "b in F(n+1) = (1 - b) F(n) + b [T] F(n); 1 is the thesis's undamped eq. 4.33")
      ->default_val(0.5)
      ->check(cli::in_range(0.0, 1.0, Ends::open_low));
  wind->add_option("--ustar", u_star, "wind-shear velocity above the saltation layer, cm/s")
      ->default_val(35)
      ->check(cli::in_range(0.0, 1000.0, Ends::open));
  wind->add_option("--tolerance", tolerance,
                   "largest relative change of F and u(y) at convergence (thesis: 0.01)")
      ->default_val(1e-3)
      ->check(cli::in_range(1e-8, 0.5));
  wind->add_option("--trajectory-tolerance", trajectory_tolerance,
                   "error per integrator step of each flight (relative; absolute in d and sqrt(g d))")
      ->default_val(1e-8)
      ->check(cli::in_range(1e-14, 1e-2));
  wind->add_option("--sample-interval", sample_interval,
                   "s between the points of a flight that feed the height profiles")
      ->default_val(5e-4)
      ->check(cli::in_range(1e-6, 0.1));
  wind->add_flag("--json", wind_json,
                 "print u_star_eff, mass_flux, iterations, converged, hop and impact means");
}

void SaltationCommands::add_study() {
  study = group->add_subcommand(
      "study",
      "the wind-driven model over planets, grain sizes and u*: threshold, flux beside the classic laws");
  study->add_option("--case", study_case, "analytic splash: CASE 1-6 of Table 4.3, scaled by sqrt(g d)")
      ->default_val(1)
      ->check(cli::in_range(1, 6));
  study->add_option("--planet", planets, "earth, mars, venus (several allowed)")->delimiter(',');
  study->add_option("--diameters", diameters, "grain diameters, cm")
      ->delimiter(',')
      ->check(cli::in_range(0.0, 1.0, Ends::open));
  study->add_option("--ustar-factors", ustar_factors, "u* as multiples of the impact threshold u*_t")
      ->delimiter(',')
      ->check(cli::in_range(1.0, 20.0, Ends::open));
  study->add_option("--grain-density", grain_density, "g/cm^3")
      ->default_val(2.6)
      ->check(cli::in_range(0.1, 20.0, Ends::open));
  study->add_option("--out,-o", study_out, "output folder: study.csv, study.json, plots")
      ->check(cli::output_folder())
      ->required();
  study->add_flag("--force", force, "replace --out");
  study->add_flag("--json", study_json, "print the thresholds and every run as JSON");
  study->add_flag("--quiet", quiet, "no progress lines");
  study->add_option("--restart", study_restart, "resume from OUT.checkpoint.json (written after every run)")
      ->check(CLI::ExistingFile);
  study->add_option("--stop-after", study_stop_after, "stop after this many new runs, leaving the checkpoint")
      ->check(cli::in_range(1, 1000000));
}

void SaltationCommands::add_dem() {
  dem_app = group->add_subcommand(
      "dem", "saltation from first principles: a periodic DEM bed under a wind the grains slow down");
  dem_app->add_option("--ustar", dem.u_star, "wind-shear velocity, cm/s")
      ->default_val(40)
      ->check(cli::in_range(0.0, 1000.0));
  dem_app->add_option("--diameter", dem.diameter, "mean grain diameter, cm")
      ->default_val(0.025)
      ->check(cli::in_range(1e-4, 1.0));
  dem_app->add_option("--polydispersity", dem.polydispersity, "radii uniform in mean x (1 +- this)")
      ->default_val(0.15)
      ->check(cli::in_range(0.0, 0.5));
  dem_app->add_option("--columns", dem.columns, "grains per layer (bed width = columns x 1.38 d)")
      ->default_val(400)
      ->check(cli::in_range(8, 1000000));
  dem_app->add_option("--layers", dem.layers, "layers of the bed")
      ->default_val(12)
      ->check(cli::in_range(2, 10000));
  dem_app->add_option("--k-n", dem.k_n, "contact stiffness, dyn/cm (reduced; k_s = k_n / 2)")
      ->default_val(2e5)
      ->check(cli::in_range(1e2, 1e12));
  dem_app->add_option("--restitution", dem.restitution, "normal restitution")
      ->default_val(0.9)
      ->check(cli::in_range(0.0, 1.0));
  dem_app->add_option("--mu", dem.mu, "friction coefficient")
      ->default_val(0.5)
      ->check(cli::in_range(0.0, 10.0));
  dem_app->add_option("--duration", dem.duration, "physical time, s")
      ->default_val(2.0)
      ->check(cli::in_range(1e-3, 1e4));
  dem_app->add_option("--average-from", dem.average_from, "start of the steady-state window, s")
      ->default_val(1.0)
      ->check(cli::in_range(0.0, 1e4));
  dem_app
      ->add_option("--kick-speed", dem.kick_speed,
                   "speed of the grains thrown to start saltation, cm/s (0: none)")
      ->default_val(100)
      ->check(cli::in_range(0.0, 1e4));
  dem_app->add_option("--sample-interval", dem.sample_interval, "s between samples of every grain")
      ->default_val(1e-4)
      ->check(cli::in_range(1e-7, 1.0));
  dem_app->add_option("--skin", dem.skin, "neighbour-list skin, cm (0: a quarter of the smallest radius)")
      ->default_val(0.0125)
      ->check(cli::in_range(0.0, 1.0));
  dem_app->add_option("--seed", dem.seed, "seed of the bed's radii")->default_val(18);
  dem_app->add_option("--out,-o", dem_out, "output folder: JSON, profiles, time series, splash.h5, plots")
      ->check(cli::output_folder());
  dem_app->add_flag("--force", force, "replace --out");
  dem_app->add_flag("--json", dem_json, "print the result as JSON");
  dem_app->add_flag("--quiet", quiet, "no progress bar");
  dem_app->add_option("--checkpoint", dem.checkpoint, "write the run's state to this HDF5 file as it goes")
      ->check(cli::output_file());
  dem_app->add_option("--checkpoint-every", dem.checkpoint_every, "s of physical time between checkpoints")
      ->default_val(0.1)
      ->check(cli::in_range(1e-6, 1e6));
  dem_app->add_option("--restart", dem.restart, "continue from a --checkpoint file (same options)")
      ->check(CLI::ExistingFile);
  dem_app->add_option("--stop-at", dem.stop_at, "stop at this time after writing the checkpoint, s")
      ->check(cli::positive());
}

void SaltationCommands::add_heights() {
  heights = group->add_subcommand(
      "heights", "Fig. 4.22: how high grains of each size rise when launched into a sediment-free wind");
  heights_spec = validation::fig4_22_spec();
  heights->add_option("--ustar", heights_spec.u_star, "wind-shear velocity, cm/s")
      ->capture_default_str()
      ->check(cli::in_range(1e-3, 1e4));
  heights->add_option("--roughness", heights_spec.roughness, "roughness length of the surface, cm")
      ->capture_default_str()
      ->check(cli::in_range(1e-6, 100.0));
  heights->add_option("--diameters", heights_spec.diameters, "grain diameters, cm")
      ->delimiter(',')
      ->capture_default_str()
      ->check(cli::in_range(1e-5, 10.0));
  heights->add_option("--angles", heights_spec.angles, "launch directions from the vertical, downwind, deg")
      ->delimiter(',')
      ->capture_default_str()
      ->check(cli::in_range(0.0, 89.9));
  heights->add_option("--speeds", heights_spec.speeds, "vertical launch speeds, cm/s")
      ->delimiter(',')
      ->check(cli::in_range(1e-3, 1e5));
  heights->add_option("--grain-density", heights_spec.grain_density, "g/cm^3")
      ->capture_default_str()
      ->check(cli::in_range(0.1, 20.0));
  heights->add_option("--out,-o", heights_out, "output folder: heights.csv and fig4_22.png")
      ->check(cli::output_folder());
  heights->add_flag("--force", force, "replace files in --out");
  heights->add_flag("--json", heights_json, "print every launch as JSON");
}

void SaltationCommands::add_transient() {
  transient = group->add_subcommand(
      "transient",
      "eq. 4.35: saltation in time from a seed of launches, through saturation and changes of u*");
  transient
      ->add_option("--case", transient_case,
                   "splash: CASE 1-6 of Table 4.3, or 7: the sand gun's (grains 0.078 cm unless "
                   "--grain-diameter says otherwise)")
      ->capture_default_str()
      ->check(cli::in_range(1, kSandGunCase));
  transient->add_option("--splash", transient_splash, "a grainlab-splash/1 file instead of a CASE")
      ->check(CLI::ExistingFile);
  transient->add_option("--ustar", transient_ustar, "wind-shear velocity at the start, cm/s")
      ->capture_default_str()
      ->check(cli::in_range(0.1, 999.0));
  transient
      ->add_option("--change", transient_changes,
                   "a time (s) and the u* (cm/s) from then on; repeat for more changes (a gust: two)")
      ->expected(2)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  transient->add_option("--duration", transient_duration, "s")
      ->capture_default_str()
      ->check(cli::in_range(0.01, 1000.0));
  transient->add_option("--dt", transient_dt, "time step, s (flight times are rounded to it)")
      ->capture_default_str()
      ->check(cli::in_range(1e-5, 0.1));
  transient->add_option("--record", transient_record, "s between recorded samples")
      ->capture_default_str()
      ->check(cli::in_range(1e-5, 100.0));
  transient_diameter_option = transient->add_option("--grain-diameter", grain_diameter, "cm (CASE 7: 0.078)")
                                  ->capture_default_str()
                                  ->check(cli::in_range(1e-4, 1.0));
  transient->add_option("--out,-o", transient_out, "output folder: transient.csv, transient.json, plots")
      ->check(cli::output_folder());
  transient->add_flag("--force", force, "replace files in --out");
  transient->add_flag("--json", transient_json, "print the summary as JSON");
  transient
      ->add_option("--checkpoint", transient_checkpoint, "save the run's state to this HDF5 file as it goes")
      ->check(cli::output_file());
  transient
      ->add_option("--checkpoint-every", transient_checkpoint_every, "s of wall time between checkpoints")
      ->capture_default_str()
      ->check(cli::in_range(0.0, 1e6));
  transient
      ->add_option("--restart", transient_restart, "continue from a --checkpoint file (the same options)")
      ->check(CLI::ExistingFile);
  transient
      ->add_option("--stop-at", transient_stop_at, "stop at this simulated time (s) after saving the state")
      ->check(cli::positive());
}

int SaltationCommands::dispatch() const {
  if (wind && *wind) return wind_command(*this);
  if (study && *study) return study_command(*this);
  if (dem_app && *dem_app) return dem_command(*this);
  if (heights && *heights) return heights_command(*this);
  if (transient && *transient) return transient_command(*this);
  if (!conveyor || !*conveyor) return -1;
  return case_name == "D" || case_name == "E" ? map_case(*this) : distribution_case(*this);
}

std::string case_label(int splash_case, const std::string& file) {
  if (!file.empty()) return file;
  if (splash_case == kSandGunCase) return "CASE 7 (the sand gun, Tables 3.11-3.12)";
  return fmt::format("CASE {} of Table 4.3", splash_case);
}

double case_grain_diameter(int splash_case, const CLI::Option* diameter_option, double diameter) {
  const bool given = diameter_option && diameter_option->count() > 0;
  return splash_case == kSandGunCase && !given ? saltation::sand_gun_splash().grain_diameter_cm : diameter;
}

saltation::SplashKernel case_splash(int splash_case, const std::string& file,
                                    const saltation::WindModelOptions& o, double scale) {
  using namespace saltation;
  if (!file.empty()) return kernel_of(read_splash_file(file), o);
  if (splash_case == kSandGunCase) return kernel_of(sand_gun_splash(), o);
  return kernel_of(scaled(table_4_3(splash_case), scale));
}

}  // namespace grainlab::cli
