#include "transient.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

namespace grainlab::saltation {

namespace {

// The grains that land at one step: per launch bin their number (per cm^2) and summed impact velocity,
// and what their flights added to the air's drag, the mass flux and the airborne count, to be taken away
// when they land.
struct Landing {
  std::vector<double> count, vx, vy, drag;
  double flux = 0, airborne = 0;
  Landing(std::size_t bins, std::size_t heights) : count(bins), vx(bins), vy(bins), drag(heights) {}
};

void check(const TransientOptions& o) {
  if (!(o.dt > 0) || !std::isfinite(o.dt)) throw std::invalid_argument("the time step must be positive");
  if (!(o.duration >= o.dt) || !std::isfinite(o.duration))
    throw std::invalid_argument("the duration must be at least one time step");
  if (!(o.model.u_star > 0)) throw std::invalid_argument("u* must be positive");
  if (o.record_every < 1) throw std::invalid_argument("record_every must be at least 1");
  double last = 0;
  for (const auto& [t, u] : o.ustar_changes) {
    if (!(t > last) || !std::isfinite(t))
      throw std::invalid_argument("the changes of u* must come in increasing time, after 0");
    if (!(u > 0) || !std::isfinite(u)) throw std::invalid_argument("a changed u* must be positive");
    last = t;
  }
}

// Means of the flux and u*_eff over the run's last fifth, and when the flux last entered 5 % of that mean
// (counted from `since`); -1 if it was outside it during the last fifth.
void summarise(TransientResult& r, double since) {
  const std::size_t n = r.samples.size();
  if (n == 0) return;
  const std::size_t tail = n - std::max<std::size_t>(1, n / 5);
  double q = 0, u = 0;
  for (std::size_t i = tail; i < n; ++i) q += r.samples[i].mass_flux, u += r.samples[i].u_star_eff;
  r.final_mass_flux = q / static_cast<double>(n - tail),
  r.final_u_star_eff = u / static_cast<double>(n - tail);
  const TransientSample &a = r.samples[tail], &b = r.samples.back();
  if (a.airborne > 0 && b.airborne > 0 && b.t > a.t)
    r.final_growth_rate = std::log(b.airborne / a.airborne) / (b.t - a.t);
  auto inside = [&](const TransientSample& s) {
    return std::abs(s.mass_flux - r.final_mass_flux) <= 0.05 * r.final_mass_flux;
  };
  std::size_t first = n;
  while (first > 0 && inside(r.samples[first - 1])) --first;
  if (first <= tail && r.final_mass_flux > 0) r.settling_time = std::max(0.0, r.samples[first].t - since);
}

}  // namespace

TransientResult run_transient(const TransientOptions& opt, const SplashKernel& splash) {
  check(opt);
  const auto start = std::chrono::steady_clock::now();
  TransientResult r;
  WindModelOptions o = opt.model;
  const std::vector<double> y = height_nodes(o), edges = bin_edges(y);
  const std::size_t H = y.size(), M = static_cast<std::size_t>(o.bins);
  const double m = o.grain.mass(), rho = o.fluid.density;
  std::vector<double> v_launch(M), vox(M, 0.0);
  for (std::size_t j = 0; j < M; ++j) v_launch[j] = (j + 0.5) * o.dv;
  // The seed: the steady solver's start, launched during the first step.
  std::vector<double> born(M, 0.0);
  for (std::size_t j = 0; j < M; ++j)
    born[j] = (o.start.empty() ? std::exp(-v_launch[j] / 100) / 100 : o.start.at(j)) * o.dv * opt.dt;
  std::map<long, Landing> landings;
  std::vector<double> drag(H, 0.0), u, tau_edge, impulse(H);
  double flux = 0, airborne = 0, since = 0, most = 0;  // most: the largest airborne count so far
  const long steps = std::lround(opt.duration / opt.dt);
  std::size_t next_change = 0;
  for (long n = 0; n <= steps; ++n) {
    const double t = static_cast<double>(n) * opt.dt;
    while (next_change < opt.ustar_changes.size() && opt.ustar_changes[next_change].first <= t + 1e-12)
      o.u_star = opt.ustar_changes[next_change].second, since = t, ++next_change;
    // The wind of this instant follows the drag of every grain in the air, those landing now included, so
    // that a flight of F steps weighs on the wind (and on the samples) at F steps.
    wind_from_drag(o, y, drag, u, tau_edge);
    const TransientSample now{t,        o.u_star, 0,
                              airborne, flux,     std::sqrt(std::max(0.0, tau_edge.front()) / rho)};
    // The grains landing now leave the air and splash the next ones up.
    if (auto it = landings.find(n); it != landings.end()) {
      const Landing& L = it->second;
      for (std::size_t k = 0; k < H; ++k) drag[k] -= L.drag[k];
      flux -= L.flux, airborne -= L.airborne;
      if (n > 0) {  // their splash: the next launches (eq. 4.34 per impact, the mean impact of each bin)
        std::fill(born.begin(), born.end(), 0.0);
        std::vector<double> sx(M, 0.0);
        for (std::size_t j = 0; j < M; ++j) {
          if (!(L.count[j] > 0)) continue;
          const double vix = L.vx[j] / L.count[j], viy = L.vy[j] / L.count[j],
                       vx0 = splash.launch_vx(vix, viy);
          for (std::size_t k = 0; k < M; ++k) {
            const double b = splash.density(v_launch[k], vix, viy) * L.count[j] * o.dv;
            born[k] += b, sx[k] += b * vx0;
          }
        }
        for (std::size_t k = 0; k < M; ++k) vox[k] = born[k] > 0 ? sx[k] / born[k] : 0;
      }
      landings.erase(it);
    } else if (n > 0) {
      std::fill(born.begin(), born.end(), 0.0);
    }
    // Launches: each bin's grains fly through this wind; their drag is spread evenly over their flight.
    double launched = 0, all = 0;
    for (double b : born) all += b;
    for (std::size_t k = 0; k < M; ++k) {
      // (Bins under 1e-12 of the launches, the splash's far tails, are not flown: they could not change a
      // printed digit, and they are half the flights.)
      if (!(born[k] > 1e-12 * all)) continue;
      std::fill(impulse.begin(), impulse.end(), 0.0);
      const Trajectory f = fly(o, y, u, vox[k], v_launch[k], &edges, &impulse, born[k]);
      const long flight = std::max(1L, std::lround(f.time / opt.dt));
      const double duration = static_cast<double>(flight) * opt.dt;
      Landing& L = landings.try_emplace(n + flight, M, H).first->second;
      L.count[k] += born[k], L.vx[k] += born[k] * f.v_ix, L.vy[k] += born[k] * f.v_iy;
      for (std::size_t b = 0; b < H; ++b) {
        const double rate = impulse[b] / duration;
        drag[b] += rate, L.drag[b] += rate;
      }
      const double q = born[k] * m * f.length / duration;
      flux += q, L.flux += q, airborne += born[k], L.airborne += born[k];
      launched += born[k];
    }
    if (n % opt.record_every == 0) {
      r.samples.push_back(now);
      r.samples.back().launch_rate = launched / opt.dt;
    }
    most = std::max(most, airborne);
    if (landings.empty() || airborne <= 1e-9 * most) {
      r.died = true;
      r.failure = "the flux died out: u* is below the impact threshold for this splash";
      break;
    }
    // The grains can carry at most the whole stress: far beyond it the splash replaces each grain more
    // than once however weak the wind (as in the steady solver).
    if (!std::isfinite(airborne) || launched / opt.dt * m * o.u_star > 100 * rho * o.u_star * o.u_star) {
      r.failure = "the flux grows without bound: this splash replaces each grain more than once";
      break;
    }
  }
  summarise(r, since);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace grainlab::saltation
