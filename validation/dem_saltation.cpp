#include "dem_saltation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "dem_saltation_state.hpp"
#include "impact_bed.hpp"
#include "parallel.hpp"
#include "scene.hpp"
#include "splash_measurement.hpp"
#include "world.hpp"

namespace grainlab::validation {

namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kG = 981;

double grain_mass(const DemSaltationOptions& o, double d) {
  return o.grain_density * M_PI / 6 * d * d * d;
}

using namespace dem_saltation_detail;

// Profile bins: half a diameter from 5 d below the bed to 400 d above it.
constexpr std::size_t kProfileBins = 810;
constexpr double kProfileFloor = -5;  // diameters

// Every hop, and the saltating ones (higher than `salton_height`) apart: their impacts are the ones the
// classic saltation numbers (impact speed nearly independent of u*) are about.
void summarize_flights(const std::vector<Flight>& flights, double salton_height, DemSaltationResult& r) {
  std::vector<double> hh, hl, sh, sl, ss, sa;
  for (const Flight& f : flights) {
    hh.push_back(f.height), hl.push_back(f.length);
    if (f.height < salton_height) continue;
    sh.push_back(f.height), sl.push_back(f.length);
    ss.push_back(std::hypot(f.impact_vx, f.impact_vy)),
        sa.push_back(std::atan2(-f.impact_vy, f.impact_vx) / kDeg);
  }
  r.hop_height = mean_interval(hh), r.hop_length = mean_interval(hl);
  r.salton_hop_height = mean_interval(sh), r.salton_hop_length = mean_interval(sl);
  r.salton_impact_speed = mean_interval(ss), r.salton_impact_angle = mean_interval(sa);
}

// Linear interpolation of a crossing of height `level` between two samples.
Crossing crossing(const GrainTrack& a, double t0, double xa, double y1, double vx1, double vy1, double x1,
                  double t1, double level, std::size_t grain) {
  const double f = std::clamp((level - a.y) / (y1 - a.y), 0.0, 1.0);
  return {t0 + f * (t1 - t0), xa + f * (x1 - xa), a.vx + f * (vx1 - a.vx), a.vy + f * (vy1 - a.vy), grain};
}

// The mean of a time series with a 95 % interval from block means. The flux fluctuates on ~0.1 s (the
// grains' drag response), so blocks are at least that long (3 to 10 of them; mean_interval's Student t
// suits so few): block means closer in time than that are not independent.
MeanInterval block_interval(const std::vector<double>& series, double sample_interval) {
  const double window = static_cast<double>(series.size()) * sample_interval;
  const std::size_t blocks = std::clamp<std::size_t>(static_cast<std::size_t>(window / 0.1), 3, 10);
  if (series.size() < blocks) return mean_interval(series);
  std::vector<double> means;
  const std::size_t per = series.size() / blocks;
  for (std::size_t b = 0; b < blocks; ++b) {
    double s = 0;
    for (std::size_t k = b * per; k < (b + 1) * per; ++k) s += series[k];
    means.push_back(s / static_cast<double>(per));
  }
  return mean_interval(means);
}

double mean_of(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double s = 0;
  for (std::size_t k = from; k < to; ++k) s += v[k];
  return to > from ? s / static_cast<double>(to - from) : 0.0;
}

// The splash from the impacts and lift-offs: a lift-off of the impacting grain within the window is its
// rebound; any other lift-off within the window and reach is an ejectum of the nearest such impact.
saltation::SplashFile measure_dem_splash(const DemSaltationOptions& o, const std::vector<Crossing>& impacts,
                                         const std::vector<Crossing>& liftoffs, double width) {
  saltation::SplashFile f;
  const double d = o.diameter, u = std::sqrt(kG * d);
  f.text = {{"schema", saltation::kSplashSchema},
            {"kind", "simulated"},
            {"source", "grainlab saltation dem: impacts in steady saltation (2-D DEM, wind_drag)"},
            {"engine", "native"},
            {"u_star_cm_s", fmt::format("{}", o.u_star)},
            {"grid", "impact speed quantiles at the median impact angle"}};
  f.grain_diameter_cm = d, f.gravity_cm_s2 = kG, f.grain_density = o.grain_density;
  if (impacts.empty()) return f;
  struct Outcome {
    bool rebounded = false;
    Crossing rebound{};
    std::vector<Crossing> ejecta;
  };
  std::vector<Outcome> out(impacts.size());
  // Impacts by time (they are recorded in time order): for each lift-off, the impacts in its window.
  std::size_t first = 0;
  const double reach = o.splash_reach * d;
  for (const Crossing& l : liftoffs) {
    while (first < impacts.size() && impacts[first].t < l.t - o.splash_window) ++first;
    long own = -1, nearest = -1;
    double best = 1e300;
    for (std::size_t k = first; k < impacts.size() && impacts[k].t < l.t; ++k) {
      if (impacts[k].grain == l.grain) own = static_cast<long>(k);
      double dx = std::fmod(std::abs(l.x - impacts[k].x), width);
      dx = std::min(dx, width - dx);
      if (impacts[k].grain != l.grain && dx < reach && dx < best) best = dx, nearest = static_cast<long>(k);
    }
    if (own >= 0 && !out[own].rebounded) {
      out[own].rebounded = true, out[own].rebound = l;
    } else if (own < 0 && nearest >= 0) {
      out[nearest].ejecta.push_back(l);
    }
  }
  // Cells: up to five speed quantiles (at least 20 impacts each) at the median angle.
  std::vector<std::size_t> order(impacts.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  auto speed = [&](std::size_t k) { return std::hypot(impacts[k].vx, impacts[k].vy); };
  auto angle = [&](std::size_t k) { return std::atan2(-impacts[k].vy, impacts[k].vx) / kDeg; };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return speed(a) < speed(b); });
  std::vector<double> angles;
  for (std::size_t k = 0; k < impacts.size(); ++k) angles.push_back(angle(k));
  std::nth_element(angles.begin(), angles.begin() + static_cast<long>(angles.size() / 2), angles.end());
  f.angles_deg = {angles[angles.size() / 2]};
  const std::size_t cells = std::clamp<std::size_t>(impacts.size() / 20, 1, 5);
  for (std::size_t c = 0; c < cells; ++c) {
    const std::size_t lo = c * order.size() / cells, hi = (c + 1) * order.size() / cells;
    saltation::SplashCell cell;
    std::vector<double> sp, ix, iy, ie, th, count, evx, evy, esp, ean, rep;
    std::size_t rebounds = 0;
    for (std::size_t q = lo; q < hi; ++q) {
      const std::size_t k = order[q];
      const Crossing& i = impacts[k];
      const Outcome& r = out[k];
      const double index = static_cast<double>(q - lo);
      sp.push_back(speed(k) / u);
      cell.rebound.push_back({index, r.rebounded ? 1.0 : 0.0, r.rebounded ? r.rebound.vx / u : 0.0,
                              r.rebounded ? r.rebound.vy / u : 0.0, 0.0});
      if (r.rebounded) {
        ++rebounds;
        ix.push_back(r.rebound.vx / i.vx), iy.push_back(-r.rebound.vy / i.vy);
        ie.push_back(std::hypot(r.rebound.vx, r.rebound.vy) / speed(k));
        th.push_back(std::atan2(r.rebound.vx, r.rebound.vy) / kDeg);
      }
      count.push_back(static_cast<double>(r.ejecta.size()));
      for (const Crossing& e : r.ejecta) {
        // Measured one diameter above the bed; carried back to the bed surface for the launch velocity.
        const double vy0 = std::sqrt(e.vy * e.vy + 2 * kG * d);
        double dx = e.x - i.x;
        dx -= width * std::round(dx / width);
        cell.ejecta.push_back({index, e.vx / u, e.vy / u, e.vx / u, vy0 / u, dx / d, 0.0, 0.0});
        evx.push_back(e.vx / u), evy.push_back(vy0 / u), esp.push_back(std::hypot(e.vx, vy0) / u);
        ean.push_back(std::atan2(e.vx, vy0) / kDeg), rep.push_back(2 * e.vx * vy0 / kG / d);
      }
    }
    cell.speed = mean_interval(sp).mean, cell.angle_deg = f.angles_deg[0], cell.impacts = hi - lo;
    set_cell_moments(cell, {hi - lo, rebounds, ix, iy, ie, th, count, evx, evy, esp, ean, rep});
    f.speeds.push_back(cell.speed);
    f.cells.push_back(std::move(cell));
  }
  return f;
}

std::string kick_row(const DemSaltationOptions& o, double spacing) {
  if (o.kick_speed <= 0 || o.columns < 8) return {};
  return fmt::format(
      "[[assemblies]]\ntype = \"lattice\"\nnx = {n}\nny = 1\nspacing = {sp:.17g}\n"
      "origin = [{x:.17g}, {y:.17g}]\nsphere_density = {rg:.17g}\nvelocity = [{v:.17g}, 0.0]\nradius = "
      "{r:.17g}\n",
      fmt::arg("n", o.columns / 8), fmt::arg("sp", 8 * spacing), fmt::arg("x", 4 * spacing),
      fmt::arg("y", (o.layers + 0.5) * spacing + 20 * o.diameter), fmt::arg("rg", o.grain_density),
      fmt::arg("v", o.kick_speed), fmt::arg("r", o.diameter / 2));
}

void compare_with_steady_model(const DemSaltationOptions& o, DemSaltationResult& r) {
  saltation::WindModelOptions m;
  m.fluid.density = o.fluid_density, m.fluid.viscosity = o.viscosity, m.fluid.k = 1 / 0.4;
  m.grain.radius = o.diameter / 2, m.grain.density = o.grain_density;
  m.g = kG, m.buoyancy = true, m.u_star = o.u_star;
  const saltation::WindModelResult w = saltation::solve_wind_model(m, saltation::kernel_of(r.splash, m));
  r.model = {true, w.converged, w.failure, w.mass_flux, w.u_star_eff, w.mean_hop_height, w.mean_hop_length};
}

}  // namespace

std::string dem_saltation_scene(const DemSaltationOptions& o) {
  const double r = o.diameter / 2, spacing = 1.2 * o.diameter * (1 + o.polydispersity);
  const double m = grain_mass(o, o.diameter);
  const double dt = contact_time(o.k_n, m, m) / o.steps_per_contact;
  return fmt::format(
      "[scene]\nname = \"DEM saltation, u* = {us} cm/s\"\nduration = {T:.17g}\nseed = {seed}\n"
      "periodic_x = [0.0, {L:.17g}]\n"
      "effects = [\"gravity\", \"normal_contact\", \"friction\", \"rotation\", \"wind_drag\", \"buoyancy\"]\n"
      "[accuracy]\nintegrator = \"verlet\"\ndt = {dt:.17g}\n{skin}"
      "[materials.sand]\nk_n = {k:.17g}\nrestitution = {e:.17g}\nk_s = {ks:.17g}\nmu = {mu:.17g}\n"
      "[fluid]\ndensity = {rf:.17g}\nviscosity = {nu:.17g}\ngrain_density = {rg:.17g}\n"
      "[wind]\nmodel = \"mixing_length\"\nu_star = {us:.17g}\nupdate_interval = {wu:.17g}\n"
      "[[walls]]\ntype = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n"
      "[[assemblies]]\ntype = \"lattice\"\nnx = {nx}\nny = {ny}\nspacing = {sp:.17g}\n"
      "origin = [{h:.17g}, {h:.17g}]\nsphere_density = {rg:.17g}\n"
      "[assemblies.radius_distribution]\nkind = \"uniform\"\nmin = {rmin:.17g}\nmax = {rmax:.17g}\n{kick}",
      fmt::arg("us", o.u_star), fmt::arg("T", o.duration), fmt::arg("seed", o.seed),
      fmt::arg("L", o.columns * spacing), fmt::arg("dt", dt), fmt::arg("k", o.k_n),
      fmt::arg("e", o.restitution), fmt::arg("ks", 0.5 * o.k_n), fmt::arg("mu", o.mu),
      fmt::arg("rf", o.fluid_density), fmt::arg("nu", o.viscosity), fmt::arg("rg", o.grain_density),
      fmt::arg("wu", o.wind_update),
      fmt::arg("skin", o.skin > 0 ? fmt::format("skin = {:.17g}\n", o.skin) : std::string()),
      fmt::arg("nx", o.columns), fmt::arg("ny", o.layers), fmt::arg("sp", spacing),
      fmt::arg("h", spacing / 2), fmt::arg("rmin", r * (1 - o.polydispersity)),
      fmt::arg("rmax", r * (1 + o.polydispersity)), fmt::arg("kick", kick_row(o, spacing)));
}

namespace {

// One sample of every grain at time t: crossings, flights, the flux, and (in the window) the profiles.
void take_sample(const DemSaltationOptions& o, const dem::Particles& p, const dem::WindField& wind, double t,
                 bool first, double width, double area, StudyState& s) {
  const dem::WindField::Snapshot& w = wind.snapshot();
  const double bed = w.bed_level, d = o.diameter, dz = 0.5 * d, z_lo = kProfileFloor * d;
  const bool in_window = t >= o.average_from - 1e-12;
  if (s.track.empty()) s.track.resize(p.size());
  double q = 0;
  std::size_t air = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    GrainTrack& g = s.track[i];
    const double level = bed + 2 * p.r[i];
    double dx = p.x[i] - g.x;
    if (!first) dx -= width * std::round(dx / width);
    const double xu = !first ? g.x_unwrapped + dx : p.x[i];
    const bool up = p.y[i] > level;
    if (!first && up != g.airborne) {
      const Crossing c =
          crossing(g, t - o.sample_interval, g.x_unwrapped, p.y[i], p.vx[i], p.vy[i], xu, t, level, i);
      if (up) {
        g.up = c, g.peak = p.y[i] - bed;
        if (in_window) s.liftoffs.push_back(c);
      } else {
        if (in_window) s.impacts.push_back(c);
        if (g.up.t >= o.average_from) s.flights.push_back({g.up.t, g.peak, c.x - g.up.x, c.vx, c.vy});
      }
    }
    if (up) g.peak = std::max(g.peak, p.y[i] - bed), ++air;
    g.airborne = up, g.x = p.x[i], g.y = p.y[i], g.vx = p.vx[i], g.vy = p.vy[i], g.x_unwrapped = xu;
    q += p.m[i] * p.vx[i];
    if (in_window) {
      const double k = std::floor((p.y[i] - bed - z_lo) / dz);
      if (k >= 0 && k < static_cast<double>(kProfileBins)) {
        s.mass_z[static_cast<std::size_t>(k)] += p.m[i];
        s.flux_z[static_cast<std::size_t>(k)] += p.m[i] * p.vx[i];
      }
    }
  }
  if (s.next_sample % 10 == 0) s.series.push_back({t, q / area, w.u_star_eff, static_cast<double>(air)});
  if (!in_window) return;
  s.window.push_back({q / area, w.u_star_eff, static_cast<double>(air), w.applied_per_area, w.drag_per_area,
                      w.stress_partition, std::abs(w.applied_per_area - w.drag_per_area)});
  for (std::size_t k = 0; k < kProfileBins; ++k) {
    const double y = bed + z_lo + (static_cast<double>(k) + 0.5) * dz;
    s.wind_z[k] += wind.u_at(y);
    const double sk = (y - w.y.front()) / (w.y[1] - w.y[0]);
    const std::size_t e = static_cast<std::size_t>(std::clamp(std::round(sk), 0.0, double(w.y.size() - 1)));
    s.clean_z[k] += w.u_clean[e], s.tau_z[k] += w.grain_stress[e];
  }
}

std::vector<double> column(const std::vector<WindowSample>& rows, std::size_t c) {
  std::vector<double> v;
  for (const WindowSample& r : rows) v.push_back(r[c]);
  return v;
}

}  // namespace

DemSaltationResult run_dem_saltation(const DemSaltationOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const Scene scene = parse_scene(dem_saltation_scene(o), "<saltation dem>");
  dem::World world(scene, dem::Decomposition{o.distributed, 200, 1});
  const dem::WindField& wind = *world.wind();
  DemSaltationResult r;
  r.bed_width = scene.periodic_x->second - scene.periodic_x->first;
  r.slab_thickness = wind.bed_area() / r.bed_width;
  r.dt = scene.accuracy.dt;
  const double area = wind.bed_area(), d = o.diameter;
  const bool root = parallel::rank() == 0;

  StudyState s;
  if (!o.restart.empty()) {
    auto [state, study] = read_checkpoint(o.restart, o);
    world.restore_state(state);
    s = std::move(study);
  }
  s.mass_z.resize(kProfileBins), s.flux_z.resize(kProfileBins), s.wind_z.resize(kProfileBins);
  s.clean_z.resize(kProfileBins), s.tau_z.resize(kProfileBins);
  const long total_samples = std::lround(o.duration / o.sample_interval);
  const long per_checkpoint = std::max(1L, std::lround(o.checkpoint_every / o.sample_interval));
  for (; s.next_sample <= total_samples; ++s.next_sample) {
    const double t = static_cast<double>(s.next_sample) * o.sample_interval;
    world.advance_to(t);
    const dem::Particles p = world.gather_particles();
    if (o.progress && root) o.progress(t, o.duration);
    if (root) take_sample(o, p, wind, t, s.next_sample == 0, r.bed_width, area, s);
    const bool stop = o.stop_at > 0 && t >= o.stop_at - 1e-12;
    if (!o.checkpoint.empty() && s.next_sample < total_samples &&
        (s.next_sample % per_checkpoint == 0 || stop)) {
      StudyState next = s;  // the file resumes with the sample after this one
      ++next.next_sample;
      const dem::WorldState state = world.save_state();  // collective
      if (root) write_checkpoint(o.checkpoint, o, state, next);
    }
    if (stop) {
      r.stopped = true;
      break;
    }
  }
  r.steps = world.diagnostics().steps;
  r.wind_seconds = world.diagnostics().seconds_wind;
  r.grains = s.track.size();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!root || s.window.empty() || r.stopped) return r;

  const std::vector<double> q_series = column(s.window, 0), ustar_series = column(s.window, 1);
  r.series = s.series, r.impacts = s.impacts, r.liftoffs = s.liftoffs;
  r.mass_flux = block_interval(q_series, o.sample_interval);
  r.u_star_eff = block_interval(ustar_series, o.sample_interval);
  r.airborne = block_interval(column(s.window, 2), o.sample_interval);
  r.first_half_flux = mean_of(q_series, 0, q_series.size() / 2);
  r.second_half_flux = mean_of(q_series, q_series.size() / 2, q_series.size());
  const std::size_t nw = s.window.size();
  r.grain_momentum_gain = mean_of(column(s.window, 3), 0, nw);
  r.wind_momentum_loss = mean_of(column(s.window, 4), 0, nw);
  r.stress_partition = mean_of(column(s.window, 5), 0, nw);
  r.coupling_lag = mean_of(column(s.window, 6), 0, nw);
  const double n = static_cast<double>(nw), dz = 0.5 * d, volume = dz * area;
  for (std::size_t k = 0; k < kProfileBins; ++k) {
    r.z.push_back((kProfileFloor + 0.5 * (static_cast<double>(k) + 0.5)) * d);
    r.concentration.push_back(s.mass_z[k] / (n * volume));
    r.flux_density.push_back(s.flux_z[k] / (n * volume));
    r.wind.push_back(s.wind_z[k] / n), r.wind_clean.push_back(s.clean_z[k] / n);
    r.grain_stress.push_back(s.tau_z[k] / n);
  }
  double flux_above = 0, mass_above = 0;
  for (std::size_t k = 0; k < kProfileBins; ++k)
    if (r.z[k] > d) flux_above += r.flux_density[k], mass_above += r.concentration[k];
  r.transport_velocity = mass_above > 0 ? flux_above / mass_above : 0;
  summarize_flights(s.flights, 5 * d, r);
  std::vector<double> is, ia, ls, la;
  for (const Crossing& c : r.impacts)
    is.push_back(std::hypot(c.vx, c.vy)), ia.push_back(std::atan2(-c.vy, c.vx) / kDeg);
  for (const Crossing& c : r.liftoffs)
    ls.push_back(std::hypot(c.vx, c.vy)), la.push_back(std::atan2(c.vy, c.vx) / kDeg);
  r.impact_speed = mean_interval(is), r.impact_angle = mean_interval(ia);
  r.liftoff_speed = mean_interval(ls), r.liftoff_angle = mean_interval(la);
  r.splash = measure_dem_splash(o, r.impacts, r.liftoffs, r.bed_width);
  if (o.model_comparison && !r.splash.cells.empty()) compare_with_steady_model(o, r);
  return r;
}

}  // namespace grainlab::validation
