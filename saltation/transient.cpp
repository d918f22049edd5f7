#include "transient.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

namespace grainlab::saltation {

namespace {

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
  r.final_mass_flux = q / static_cast<double>(n - tail);
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

TransientState start_transient(const TransientOptions& opt) {
  check(opt);
  const WindModelOptions& o = opt.model;
  TransientState s;
  s.u_star = o.u_star;
  const std::size_t M = static_cast<std::size_t>(o.bins);
  s.drag.assign(height_nodes(o).size(), 0.0), s.vox.assign(M, 0.0), s.born.assign(M, 0.0);
  // The seed: the steady solver's start, launched during the first step.
  for (std::size_t j = 0; j < M; ++j) {
    const double v = (j + 0.5) * o.dv;
    s.born[j] = (o.start.empty() ? std::exp(-v / 100) / 100 : o.start.at(j)) * o.dv * opt.dt;
  }
  return s;
}

long transient_last_step(const TransientOptions& o) {
  return std::lround(o.duration / o.dt);
}

bool advance_transient(const TransientOptions& opt, const SplashKernel& splash, TransientState& s,
                       long stop_step) {
  check(opt);
  WindModelOptions o = opt.model;
  const std::vector<double> y = height_nodes(o), edges = bin_edges(y);
  const std::size_t H = y.size(), M = static_cast<std::size_t>(o.bins);
  if (s.drag.size() != H || s.born.size() != M || s.vox.size() != M)
    throw std::invalid_argument("the state does not fit these options' grids");
  const double m = o.grain.mass(), rho = o.fluid.density;
  std::vector<double> v_launch(M), u, tau_edge, impulse(H), sx(M);  // (scratch kept across steps)
  for (std::size_t j = 0; j < M; ++j) v_launch[j] = (j + 0.5) * o.dv;
  const long last = std::min(stop_step, transient_last_step(opt));
  for (; !s.over && s.next_step <= last; ++s.next_step) {
    const long n = s.next_step;
    const double t = static_cast<double>(n) * opt.dt;
    while (s.next_change < opt.ustar_changes.size() && opt.ustar_changes[s.next_change].first <= t + 1e-12)
      s.u_star = opt.ustar_changes[s.next_change].second, s.since = t, ++s.next_change;
    o.u_star = s.u_star;
    // The wind of this instant follows the drag of every grain in the air, those landing now included, so
    // that a flight of F steps weighs on the wind (and on the samples) at F steps.
    wind_from_drag(o, y, s.drag, u, tau_edge);
    const TransientSample now{t,          o.u_star, 0,
                              s.airborne, s.flux,   std::sqrt(std::max(0.0, tau_edge.front()) / rho)};
    // The grains landing now leave the air and splash the next ones up (eq. 4.34 per impact, at the mean
    // impact of each launch bin's grains).
    if (auto it = s.landings.find(n); it != s.landings.end()) {
      const TransientLanding& L = it->second;
      for (std::size_t k = 0; k < H; ++k) s.drag[k] -= L.drag[k];
      s.flux -= L.flux, s.airborne -= L.airborne;
      std::fill(s.born.begin(), s.born.end(), 0.0);
      std::fill(sx.begin(), sx.end(), 0.0);
      for (std::size_t j = 0; j < M; ++j) {
        if (!(L.count[j] > 0)) continue;
        const double vix = L.vx[j] / L.count[j], viy = L.vy[j] / L.count[j], vx0 = splash.launch_vx(vix, viy);
        for (std::size_t k = 0; k < M; ++k) {
          const double b = splash.density(v_launch[k], vix, viy) * L.count[j] * o.dv;
          s.born[k] += b, sx[k] += b * vx0;
        }
      }
      for (std::size_t k = 0; k < M; ++k) s.vox[k] = s.born[k] > 0 ? sx[k] / s.born[k] : 0;
      s.landings.erase(it);
    } else if (n > 0) {
      std::fill(s.born.begin(), s.born.end(), 0.0);
    }
    // Launches: each bin's grains fly through this wind; their drag is spread evenly over their flight.
    double launched = 0, all = 0;
    for (double b : s.born) all += b;
    for (std::size_t k = 0; k < M; ++k) {
      // (Bins under 1e-12 of the launches, the splash's far tails, are not flown: they could not change a
      // printed digit, and they are half the flights.)
      if (!(s.born[k] > 1e-12 * all)) continue;
      std::fill(impulse.begin(), impulse.end(), 0.0);
      const Trajectory f = fly(o, y, u, s.vox[k], v_launch[k], &edges, &impulse, s.born[k]);
      const long flight = std::max(1L, std::lround(f.time / opt.dt));
      const double duration = static_cast<double>(flight) * opt.dt;
      auto [at, fresh] = s.landings.try_emplace(n + flight);
      TransientLanding& L = at->second;
      if (fresh) L.count.assign(M, 0.0), L.vx.assign(M, 0.0), L.vy.assign(M, 0.0), L.drag.assign(H, 0.0);
      L.count[k] += s.born[k], L.vx[k] += s.born[k] * f.v_ix, L.vy[k] += s.born[k] * f.v_iy;
      for (std::size_t b = 0; b < H; ++b) {
        const double rate = impulse[b] / duration;
        s.drag[b] += rate, L.drag[b] += rate;
      }
      const double q = s.born[k] * m * f.length / duration;
      s.flux += q, L.flux += q, s.airborne += s.born[k], L.airborne += s.born[k];
      launched += s.born[k];
    }
    if (n % opt.record_every == 0) {
      s.result.samples.push_back(now);
      s.result.samples.back().launch_rate = launched / opt.dt;
    }
    s.most = std::max(s.most, s.airborne);
    if (s.landings.empty() || s.airborne <= 1e-9 * s.most) {
      s.result.died = true, s.over = true;
      s.result.failure = "the flux died out: u* is below the impact threshold for this splash";
    } else if (!std::isfinite(s.airborne) ||
               launched / opt.dt * m * o.u_star > 100 * rho * o.u_star * o.u_star) {
      // The grains can carry at most the whole stress: far beyond it the splash replaces each grain more
      // than once however weak the wind (as in the steady solver).
      s.over = true;
      s.result.failure = "the flux grows without bound: this splash replaces each grain more than once";
    }
  }
  if (s.next_step > transient_last_step(opt)) s.over = true;
  return s.over;
}

TransientResult finish_transient(const TransientState& s) {
  TransientResult r = s.result;
  summarise(r, s.since);
  return r;
}

TransientResult run_transient(const TransientOptions& opt, const SplashKernel& splash) {
  const auto start = std::chrono::steady_clock::now();
  TransientState s = start_transient(opt);
  advance_transient(opt, splash, s, transient_last_step(opt));
  TransientResult r = finish_transient(s);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace grainlab::saltation
