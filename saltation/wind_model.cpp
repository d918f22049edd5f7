#include "wind_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

#include "convergence.hpp"
#include "fluid.hpp"

namespace grainlab::saltation {

namespace odeint = boost::numeric::odeint;

double Grain::mass() const {
  return 4.0 / 3.0 * M_PI * radius * radius * radius * density;
}

double AnalyticSplash::density(double v_oy, double v_ix, double v_iy) const {
  double s = 0;
  if (c1 > 0) {
    const double centre = f * v_ix - eps * v_iy;  // v_iy < 0: eps |v_iy| added
    s += c1 / (c2 * std::sqrt(2 * M_PI)) * (v_ix / (v_ix + c5)) *
         std::exp(-0.5 * (v_oy - centre) * (v_oy - centre) / (c2 * c2));
  }
  if (c3 > 0) s += c3 * (v_ix * v_ix + v_iy * v_iy) * std::exp(-v_oy / c4);
  return s;
}

AnalyticSplash table_4_3(int c) {
  // c1, c2, c3, c4, c5, c6, eps, f for CASES 1-6 (c4 and c5 where the table has "-" are unused).
  static const AnalyticSplash cases[6] = {
      {2, 35, 0, 40, 275, 0, 0.7, 0.1},    {2, 35, 2e-7, 40, 275, 0, 0.7, 0.1},
      {1, 35, 2e-7, 40, 275, 0, 0.7, 0.1}, {0, 35, 2e-7, 80, 275, 0, 0.7, 0.1},
      {2, 35, 0, 40, 275, 1, 0.3, 0.1},    {2, 35, 2e-7, 40, 275, 1, 0.3, 0.1}};
  if (c < 1 || c > 6) throw std::invalid_argument("Table 4.3 has CASES 1 to 6");
  return cases[c - 1];
}

std::array<double, 3> table_4_3_ustars(int c) {
  if (c >= 1 && c <= 3) return {35, 75, 125};
  if (c == 4) return {35, 50, 75};
  if (c == 5 || c == 6) return {50, 100, 150};
  throw std::invalid_argument("Table 4.3 has CASES 1 to 6");
}

// Nodes log-spaced from the roughness length to the top.
std::vector<double> height_nodes(const WindModelOptions& o) {
  std::vector<double> y(static_cast<std::size_t>(o.heights));
  const double a = std::log(o.roughness()), b = std::log(o.top);
  for (int k = 0; k < o.heights; ++k)
    y[static_cast<std::size_t>(k)] = std::exp(a + (b - a) * k / (o.heights - 1));
  return y;
}

// Bin k spans [edges[k], edges[k+1]): from 0 below the first node to far above the last.
std::vector<double> bin_edges(const std::vector<double>& y) {
  std::vector<double> e(y.size() + 1);
  e[0] = 0;
  for (std::size_t k = 1; k < y.size(); ++k) e[k] = std::sqrt(y[k - 1] * y[k]);
  e[y.size()] = 1e30;
  return e;
}

void wind_from_drag(const WindModelOptions& o, const std::vector<double>& y,
                    const std::vector<double>& impulse, std::vector<double>& u,
                    std::vector<double>& tau_edge) {
  const std::size_t H = y.size();
  const double rho = o.fluid.density;
  tau_edge.resize(H + 1);
  tau_edge[H] = rho * o.u_star * o.u_star;
  for (std::size_t k = H; k-- > 0;) tau_edge[k] = tau_edge[k + 1] - impulse[k];
  u.assign(H, 0.0);
  auto speed = [&](std::size_t k) {
    return std::sqrt(std::max(0.0, 0.5 * (tau_edge[k] + tau_edge[k + 1])) / rho);
  };
  for (std::size_t k = 1; k < H; ++k)
    u[k] = u[k - 1] + o.fluid.k * 0.5 * (speed(k - 1) + speed(k)) * std::log(y[k] / y[k - 1]);
}

namespace {

// A grain still airborne after this long (s) is left where it is: it is in suspension, not saltation.
constexpr double kLongestFlight = 1000;

// The flight's state in units of the grain (positions / d, velocities / sqrt(g d)), so that one error
// tolerance means the same for all four components.
using Flight = std::array<double, 4>;  // x, y, vx, vy

struct Scales {
  double length, speed;
};

// d(state)/dt: gravity and the drag of eqs 4.30-4.31 in the wind u(y).
void flight_rate(const WindModelOptions& o, const std::vector<double>& ys, const std::vector<double>& u,
                 const Scales& s, double drag_factor, const Flight& z, Flight& dz) {
  const double y = z[1] * s.length, vx = z[2] * s.speed, vy = z[3] * s.speed;
  const double rx = vx - wind_at(o, ys, u, y), ry = vy;
  const double vr = std::sqrt(rx * rx + ry * ry);  // not hypot: no overflow here, and a third of the cost
  double ax = 0, ay = -(o.buoyancy ? o.g * (1 - o.fluid.density / o.grain.density) : o.g);
  if (vr > 0) {
    const double cd = fluid::drag_coefficient(
        WindSpec::DragLaw::Thesis, o.reynolds_factor * 2 * o.grain.radius * vr / o.fluid.viscosity);
    const double c = drag_factor * cd * vr;  // eq. 4.30 over the grain's mass
    ax -= c * rx, ay -= c * ry;
  }
  dz = {vx / s.length, vy / s.length, ax / s.speed, ay / s.speed};
}

// Adds `amount` over the bins that [a, b] spans, in proportion to the overlap.
void deposit(const std::vector<double>& edges, std::vector<double>& into, double a, double b, double amount) {
  if (a > b) std::swap(a, b);
  a = std::max(a, 0.0);
  if (b <= a) {
    const std::size_t k =
        static_cast<std::size_t>(std::upper_bound(edges.begin(), edges.end(), a) - edges.begin()) - 1;
    into[std::min(k, into.size() - 1)] += amount;
    return;
  }
  std::size_t k =
      static_cast<std::size_t>(std::upper_bound(edges.begin(), edges.end(), a) - edges.begin()) - 1;
  for (; k < into.size() && edges[k] < b; ++k) {
    const double lo = std::max(a, edges[k]), hi = std::min(b, edges[k + 1]);
    if (hi > lo) into[k] += amount * (hi - lo) / (b - a);
  }
}

// Each bin's drag spread evenly over `width` cm around the bin's middle, the window moved up to stay above
// the bed: the total, and so the grain-borne stress, is kept.
void smooth_drag(const std::vector<double>& edges, std::vector<double>& impulse, double width) {
  std::vector<double> out(impulse.size(), 0.0);
  for (std::size_t k = 0; k < impulse.size(); ++k) {
    if (impulse[k] == 0) continue;
    const double lo = std::max(0.0, 0.5 * (edges[k] + edges[k + 1]) - width / 2);
    deposit(edges, out, lo, lo + width, impulse[k]);
  }
  impulse.swap(out);
}

double max_relative_change(const std::vector<double>& a, const std::vector<double>& b) {
  double scale = 0, d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) scale = std::max(scale, std::abs(b[i]));
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return scale > 0 ? d / scale : (d > 0 ? 1.0 : 0.0);
}

}  // namespace

double wind_at(const WindModelOptions& o, const std::vector<double>& y, const std::vector<double>& u,
               double h) {
  if (h <= y.front()) return 0;
  if (h >= y.back()) return u.back() + o.fluid.k * o.u_star * std::log(h / y.back());
  const double t = std::log(h / y.front()) / std::log(y.back() / y.front()) * (y.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(t), y.size() - 2);
  const double w = t - k;
  return u[k] * (1 - w) + u[k + 1] * w;
}

Trajectory fly(const WindModelOptions& o, const std::vector<double>& y, const std::vector<double>& u,
               double v_ox, double v_oy, const std::vector<double>* edges, std::vector<double>* impulse,
               double weight, FlightProfiles* profiles) {
  Trajectory t;
  t.v_ox = v_ox, t.v_oy = v_oy;
  t.v_ix = v_ox, t.v_iy = v_oy;
  if (!(v_oy > 0)) return t;  // it never leaves the bed
  const double m = o.grain.mass();
  const double drag_factor = 0.5 * o.fluid.density * M_PI * o.grain.radius * o.grain.radius / m;
  const Scales sc{2 * o.grain.radius, std::sqrt(o.g * 2 * o.grain.radius)};
  auto rate = [&](const Flight& z, Flight& dz, double) { flight_rate(o, y, u, sc, drag_factor, z, dz); };
  // Dormand-Prince 5(4) with error control and its 4th-order dense output: the steps follow the error
  // (long near the apex, short where the wind's slope changes near the bed), and the dense output gives the
  // state between steps for the height bins and the landing.
  auto stepper = odeint::make_dense_output(o.trajectory_tolerance, o.trajectory_tolerance,
                                           odeint::runge_kutta_dopri5<Flight>());
  // The first step a small part of the rise time, so that it cannot jump a whole short hop.
  stepper.initialize(Flight{0, 0, v_ox / sc.speed, v_oy / sc.speed}, 0.0,
                     std::min(o.sample_interval, 0.05 * v_oy / o.g));
  Flight prev = stepper.current_state();
  double t_prev = 0;
  auto state_at = [&](double time) {
    Flight z;
    stepper.calc_state(time, z);
    return z;
  };
  // One piece of the flight, from a to b over dt: the drag's momentum and the profiles go to the height
  // bins it spans.
  auto record = [&](const Flight& a, const Flight& b, double dt) {
    const double ya = a[1] * sc.length, yb = b[1] * sc.length;
    if (impulse) deposit(*edges, *impulse, ya, yb, weight * m * (b[2] - a[2]) * sc.speed);
    if (profiles) {
      const double vx = 0.5 * (a[2] + b[2]) * sc.speed, w = weight * dt;
      deposit(*edges, profiles->time, ya, yb, w);
      deposit(*edges, profiles->number_flux, ya, yb, w * vx);
      deposit(*edges, profiles->energy_flux, ya, yb, w * 0.5 * m * vx * vx);
    }
    t.height = std::max(t.height, yb);
    t.time += dt;
  };
  auto finish = [&](const Flight& z) {
    t.v_ix = z[2] * sc.speed, t.v_iy = z[3] * sc.speed, t.length = z[0] * sc.length;
    return t;
  };
  while (t_prev < kLongestFlight) {
    const auto [t0, t1] = stepper.do_step(rate);
    ++t.steps;
    // The step in pieces of at most sample_interval: the height bins see the path, not the chord.
    const int pieces = std::max(1, static_cast<int>(std::ceil((t1 - t0) / o.sample_interval)));
    for (int i = 1; i <= pieces; ++i) {
      double ti = i == pieces ? t1 : t0 + (t1 - t0) * i / pieces;
      Flight z = i == pieces ? stepper.current_state() : state_at(ti);
      if (!std::isfinite(z[1]) || !std::isfinite(z[2]))
        return finish(prev);  // a broken wind: the caller
                              // reports it
      if (z[1] <= 0) {
        // Back at the bed: the landing time by bisection on the dense output, between the last state above
        // the bed (or the launch) and this one.
        double a = t_prev, b = ti;
        for (int k = 0; k < 80 && b - a > 1e-13 * b; ++k) {
          const double mid = 0.5 * (a + b);
          (state_at(mid)[1] > 0 ? a : b) = mid;
        }
        ti = b, z = state_at(b), z[1] = 0;
        record(prev, z, ti - t_prev);
        return finish(z);
      }
      record(prev, z, ti - t_prev);
      prev = z, t_prev = ti;
    }
  }
  return finish(prev);
}

double peak_height(const std::vector<double>& y, const std::vector<double>& v, double from) {
  double best = -1, at = 0;
  for (std::size_t k = 0; k < y.size() && k < v.size(); ++k)
    if (y[k] >= from && v[k] > best) best = v[k], at = y[k];
  return at;
}

SplashKernel kernel_of(const AnalyticSplash& s) {
  return {[s](double v_oy, double v_ix, double v_iy) { return s.density(v_oy, v_ix, v_iy); },
          [s](double v_ix, double) { return s.launch_vx(v_ix); }};
}

namespace {

// Per cell: rebounds and ejecta launched per impact per cm/s on the model's launch bins, and their mean v_x.
struct BinnedCell {
  std::vector<double> rebound, ejecta;
  double mean_vx = 0;
  double above = 0;  // grains per impact launched above the grid's top bin (lost to the model)
};

BinnedCell bin_cell(const SplashCell& c, double scale, const WindModelOptions& o) {
  BinnedCell b;
  b.rebound.assign(static_cast<std::size_t>(o.bins), 0.0);
  b.ejecta = b.rebound;
  const double per = 1.0 / (std::max<std::size_t>(c.impacts, 1) * o.dv);
  double n = 0, sx = 0;
  auto add = [&](std::vector<double>& into, double vx, double vy) {
    const long k = static_cast<long>(std::floor(vy * scale / o.dv));
    if (k >= o.bins) b.above += per * o.dv;
    if (k < 0 || k >= o.bins) return;
    into[static_cast<std::size_t>(k)] += per;
    n += 1, sx += vx * scale;
  };
  for (const ReboundRow& r : c.rebound)
    if (r[1] > 0) add(b.rebound, r[2], r[3]);
  for (const EjectumRow& e : c.ejecta) add(b.ejecta, e[3], e[4]);
  b.mean_vx = n > 0 ? sx / n : 0;
  return b;
}

// Index below x on an increasing axis and the weight of the next point (clamped at the ends).
std::pair<std::size_t, double> bracket(const std::vector<double>& axis, double x) {
  if (axis.size() < 2 || x <= axis.front()) return {0, 0.0};
  if (x >= axis.back()) return {axis.size() - 2, 1.0};
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin()) - 1;
  return {i, (x - axis[i]) / (axis[i + 1] - axis[i])};
}

}  // namespace

// A measured file with moments only (the sand gun). At each impact: a rebound drawn from a Gaussian of
// eps_iy x |v_iy| (spread likewise) from the nearest cell; ejecta numbering the least-squares line of
// ejecta per impact against impact speed across the cells (the sand gun's linear law), held at zero below
// its root, with an exponential launch v_y of the nearest cell's mean. This is the extrapolation the thesis
// made for its CASE 7 ("extrapolated outside" 650-1200 cm/s), in its simplest defensible form. A rebound
// too slow to lift the grain one diameter (v_y < sqrt(2 g d), the thesis's "infrared cutoff") leaves it in
// the bed: moments alone do not say which slow impacts trap the grain, and without this every grain
// rebounds for ever.
SplashKernel moments_kernel(const SplashFile& f, double scale, WindModelOptions::EjectaBelowRange below) {
  double sv = 0, sn = 0, svv = 0, svn = 0, m = 0, slowest = 0;
  for (const SplashCell& c : f.cells)
    if (c.moments.count("ejecta_per_impact")) {
      const double v = c.speed, n = c.moments.at("ejecta_per_impact").mean;
      sv += v, sn += n, svv += v * v, svn += v * n, m += 1;
      slowest = m == 1 ? v : std::min(slowest, v);
    }
  const double slope = m > 1 ? (m * svn - sv * sn) / (m * svv - sv * sv) : 0,
               icpt = m > 0 ? (sn - slope * sv) / m : 0;
  // Proportional: below the slowest cell, its line value times v / v_slowest.
  const double at_slowest = std::max(0.0, icpt + slope * slowest);
  const bool proportional = below == WindModelOptions::EjectaBelowRange::proportional && slowest > 0;
  auto file = std::make_shared<SplashFile>(f);
  auto near = [file, scale](double v_ix, double v_iy) -> const SplashCell& {
    return file->nearest(std::hypot(v_ix, v_iy) / scale, std::atan2(-v_iy, v_ix) * 180 / M_PI);
  };
  auto get = [](const SplashCell& c, const char* k, bool spread) {
    return c.moments.count(k) ? (spread ? c.moments.at(k).sd : c.moments.at(k).mean) : 0.0;
  };
  auto ejecta = [slope, icpt, scale, proportional, slowest, at_slowest](double v_ix, double v_iy) {
    const double v = std::hypot(v_ix, v_iy) / scale;
    if (proportional && v < slowest) return at_slowest * v / slowest;
    return std::max(0.0, icpt + slope * v);
  };
  const double trap = std::sqrt(2.0) * scale;
  return {[near, get, ejecta, scale, trap](double v_oy, double v_ix, double v_iy) {
            const SplashCell& c = near(v_ix, v_iy);
            const double mu = get(c, "eps_iy", false) * -v_iy;
            const double sig = std::max(get(c, "eps_iy", true) * -v_iy, 1e-3 * scale);
            double d = v_oy < trap ? 0.0
                                   : std::exp(-0.5 * (v_oy - mu) * (v_oy - mu) / (sig * sig)) /
                                         (sig * std::sqrt(2 * M_PI));
            const double vey = get(c, "ejecta_vy", false) * scale;
            if (vey > 0) d += ejecta(v_ix, v_iy) * std::exp(-v_oy / vey) / vey;
            return d;
          },
          [near, get, ejecta, scale](double v_ix, double v_iy) {
            const SplashCell& c = near(v_ix, v_iy);
            const double n = ejecta(v_ix, v_iy);
            const double ej_vx =
                get(c, "ejecta_vy", false) * scale * std::tan(get(c, "ejecta_angle", false) * M_PI / 180);
            return (get(c, "eps_ix", false) * v_ix + n * ej_vx) / (1 + n);
          }};
}

SplashKernel kernel_of(const SplashFile& f, const WindModelOptions& o) {
  const double scale = std::sqrt(o.g * 2 * o.grain.radius);  // the model's sqrt(g d)
  bool raw = false;
  for (const SplashCell& c : f.cells) raw = raw || !c.rebound.empty() || !c.ejecta.empty();
  if (!raw) return moments_kernel(f, scale, o.ejecta_below_range);
  auto cells = std::make_shared<std::vector<BinnedCell>>();
  for (const SplashCell& c : f.cells) cells->push_back(bin_cell(c, scale, o));
  const bool grid = !f.speeds.empty() && f.speeds.size() * f.angles_deg.size() == f.cells.size();
  auto file = std::make_shared<SplashFile>(f);
  // The weights of the cells around an impact.
  auto around = [file, grid, scale](double v_ix, double v_iy) {
    const double speed = std::hypot(v_ix, v_iy) / scale, angle = std::atan2(-v_iy, v_ix) * 180 / M_PI;
    std::vector<std::pair<std::size_t, double>> w;
    if (!grid) {
      const SplashCell* near = &file->nearest(speed, angle);
      w.push_back({static_cast<std::size_t>(near - file->cells.data()), 1.0});
      return w;
    }
    const auto [i, a] = bracket(file->speeds, speed);
    const auto [j, b] = bracket(file->angles_deg, angle);
    const std::size_t na = file->angles_deg.size();
    const std::size_t i1 = std::min(i + 1, file->speeds.size() - 1), j1 = std::min(j + 1, na - 1);
    w = {{i * na + j, (1 - a) * (1 - b)},
         {i1 * na + j, a * (1 - b)},
         {i * na + j1, (1 - a) * b},
         {i1 * na + j1, a * b}};
    return w;
  };
  // Below the slowest measured speed the splash is extrapolated self-similarly: the slowest cells' launch
  // velocities scale with the impact speed (ratio f) and their ejecta number falls linearly to zero, so a
  // slow impact does not eject what a fast one does (holding the edge cell would let creeping grains feed
  // the flux for ever).
  const double dv = o.dv, v_min = grid ? f.speeds.front() * scale : 0;
  const int bins = o.bins;
  return {[cells, around, dv, bins, v_min](double v_oy, double v_ix, double v_iy) {
            const double speed = std::hypot(v_ix, v_iy);
            const double f = speed < v_min ? std::max(speed / v_min, 1e-6) : 1.0;
            const long b = static_cast<long>(std::floor(v_oy / dv));
            if (b < 0 || b >= bins) return 0.0;
            // Grains per impact per cm/s in launch bin b: each measured bin k, compressed to
            // [k dv f, (k + 1) dv f), gives b its overlapping share (exact: every grain lands in some bin).
            double d = 0;
            const long k_lo = static_cast<long>(std::floor(b / f)),
                       k_hi = static_cast<long>(std::ceil((b + 1) / f));
            for (long k = std::max(0L, k_lo); k < std::min<long>(bins, k_hi); ++k) {
              const double share =
                  std::max(0.0, std::min<double>(b + 1, (k + 1) * f) - std::max<double>(b, k * f)) / f;
              if (share <= 0) continue;
              const auto kk = static_cast<std::size_t>(k);
              for (const auto& [c, w] : around(v_ix, v_iy))
                d += w * share * ((*cells)[c].rebound[kk] + f * (*cells)[c].ejecta[kk]);
            }
            return d;
          },
          [cells, around, v_min](double v_ix, double v_iy) {
            const double speed = std::hypot(v_ix, v_iy);
            const double f = speed < v_min ? speed / v_min : 1.0;
            double vx = 0;
            for (const auto& [c, w] : around(v_ix, v_iy)) vx += w * (*cells)[c].mean_vx;
            return f * vx;
          },
          [cells, around](double v_ix, double v_iy) {
            double n = 0;
            for (const auto& [c, w] : around(v_ix, v_iy)) n += w * (*cells)[c].above;
            return n;
          }};
}

namespace {

// Grains per impact that the splash launches above the grid's top (v_oy >= top).
double launched_above(const SplashKernel& splash, double top, double dv, const Trajectory& t) {
  if (splash.above_grid) return splash.above_grid(t.v_ix, t.v_iy);
  // A launch faster than twice the impact is beyond any splash here; the integral stops there.
  const double end = std::max(2 * top, 2 * std::hypot(t.v_ix, t.v_iy));
  double n = 0;
  for (double v = top + dv / 2; v < end; v += dv) n += splash.density(v, t.v_ix, t.v_iy) * dv;
  return n;
}

// Why the flux died: the wind was below the impact threshold, or the grid lost the fast launches that
// would have kept it going. The share of the last iteration's launches above the grid tells which.
std::string why_the_flux_died(const SplashKernel& splash, const std::vector<Trajectory>& flights,
                              const std::vector<double>& F, const std::vector<double>& v_launch,
                              const WindModelOptions& o) {
  const double top = v_launch.back() + o.dv / 2;
  double inside = 0, above = 0;
  for (std::size_t j = 0; j < F.size(); ++j) {
    if (!(F[j] > 0)) continue;
    above += F[j] * launched_above(splash, top, o.dv, flights[j]);
    for (double v : v_launch) inside += F[j] * splash.density(v, flights[j].v_ix, flights[j].v_iy) * o.dv;
  }
  const double share = above + inside > 0 ? above / (above + inside) : 0;
  if (share > 0.01)
    return fmt::format(
        "the flux died out: {:.0f} % of the grains were launched above the top of the launch grid ({:.4g} "
        "cm/s) and lost; give more --bins (now {}) or a wider --dv",
        100 * share, top, v_launch.size());
  const std::string lost =
      share < 1e-6
          ? "no launch left the top of the launch grid"
          : fmt::format("only {:.2g} % of the launches left the top of the launch grid", 100 * share);
  return fmt::format(
      "the flux died out: u* is below the impact threshold for this splash ({}; `grainlab saltation study` "
      "finds the threshold of the thesis's splash functions)",
      lost);
}

}  // namespace

namespace {

// The launch states of the fixed point: one per v_oy bin (the thesis's grid; each bin's v_ox is the mean
// of what feeds it), or with `vx_bins` > 0 one per (v_oy, v_ox) cell, each with its fixed v_ox (the 4-index
// [T] of Fig. 4.10's note). F[s] is grains per cm^2 per s per cm/s of v_oy in state s; state s = j X + x.
struct LaunchStates {
  bool grid2d = false;
  std::size_t M = 0, X = 1, S = 0;
  std::size_t first_launch = 0;  // the bins below launch_min (a prefix: the bins rise in speed) stay empty
  std::vector<double> F, vox, voy;
};

// A weak, broad start (about one launch per cm^2 per s), or the options' own: the flux grows to the steady
// state. In 2-D it starts in the cell of v_ox = 0.
LaunchStates initial_launch_states(const WindModelOptions& o, const std::vector<double>& v_launch) {
  LaunchStates l;
  l.grid2d = o.vx_bins > 0;
  l.M = v_launch.size(), l.X = l.grid2d ? static_cast<std::size_t>(o.vx_bins) : 1, l.S = l.M * l.X;
  l.F.assign(l.S, 0.0), l.vox.assign(l.S, 0.0), l.voy.assign(l.S, 0.0);
  const std::size_t m_zero = l.grid2d ? static_cast<std::size_t>(std::clamp(std::round(-o.vx_min / o.dv), 0.0,
                                                                            static_cast<double>(l.X - 1)))
                                      : 0;
  for (std::size_t j = 0; j < l.M; ++j) {
    for (std::size_t x = 0; x < l.X; ++x)
      l.voy[j * l.X + x] = v_launch[j],
                      l.vox[j * l.X + x] = l.grid2d ? o.vx_min + static_cast<double>(x) * o.dv : 0;
    l.F[j * l.X + m_zero] = v_launch[j] < o.launch_min ? 0.0
                            : o.start.empty()          ? std::exp(-v_launch[j] / 100) / 100
                                                       : o.start[j];
  }
  l.first_launch = static_cast<std::size_t>(std::lower_bound(v_launch.begin(), v_launch.end(), o.launch_min) -
                                            v_launch.begin());
  return l;
}

// F(n+1) = [T{u}] F(n), damped: each impact of a grain from state j launches S(v_k; v_i(j)) dv into bin k.
// Returns the next F; `vox_next` gets the next launch v_ox of each state.
std::vector<double> splash_step(const WindModelOptions& o, const SplashKernel& splash,
                                const std::vector<double>& v_launch, const std::vector<Trajectory>& flights,
                                const LaunchStates& l, std::vector<double>& vox_next) {
  std::vector<double> next(l.S);
  vox_next = l.vox;
  if (!l.grid2d) {
    for (std::size_t k = 0; k < l.M; ++k) {
      double s = 0, sx = 0;
      if (k >= l.first_launch)
        for (std::size_t j = 0; j < l.M; ++j) {
          const Trajectory& t = flights[j];
          const double born = splash.density(v_launch[k], t.v_ix, t.v_iy) * l.F[j] * o.dv;
          s += born, sx += born * splash.launch_vx(t.v_ix, t.v_iy);
        }
      next[k] = (1 - o.flux_damping) * l.F[k] + o.flux_damping * s;
      vox_next[k] = s > 0 ? sx / s : 0;  // one horizontal launch velocity per bin: the mean of its sources
    }
    return next;
  }
  // Each impact's grains share one v_ox (eq. 4.34's delta): they go to the two v_ox cells around it, in
  // proportion to its distance from their centres (held in the grid at its ends). The sums are damped as
  // the 1-D grid's are, so a grid whose grains all leave at one v_ox value does the 1-D grid's arithmetic,
  // bit for bit.
  std::vector<double> born_sum(l.S, 0.0);
  const std::size_t X = l.X;
  for (std::size_t j = 0; j < l.S; ++j) {
    if (l.F[j] <= 0) continue;
    const Trajectory& t = flights[j];
    const double q =
        std::clamp((splash.launch_vx(t.v_ix, t.v_iy) - o.vx_min) / o.dv, 0.0, static_cast<double>(X - 1));
    const std::size_t m0 = std::min(static_cast<std::size_t>(q), X - 1), m1 = std::min(m0 + 1, X - 1);
    const double w1 = q - static_cast<double>(m0);
    for (std::size_t k = l.first_launch; k < l.M; ++k) {
      const double born = splash.density(v_launch[k], t.v_ix, t.v_iy) * l.F[j] * o.dv;
      born_sum[k * X + m0] += (1 - w1) * born, born_sum[k * X + m1] += w1 * born;
    }
  }
  for (std::size_t s2 = 0; s2 < l.S; ++s2)
    next[s2] = (1 - o.flux_damping) * l.F[s2] + o.flux_damping * born_sum[s2];
  return next;
}

// The steady state's profiles (from sub-launches spread evenly across each bin: F is a density in v_oy,
// and one flight per bin would put all of a bin's apexes, where the 1/|v_y| density peaks, at one height),
// and its hop, impact and flux statistics.
void steady_state_diagnostics(const WindModelOptions& o, const std::vector<double>& edges,
                              const std::vector<double>& impulse, const std::vector<double>& tau_edge,
                              const std::vector<Trajectory>& flights, const LaunchStates& l,
                              WindModelResult& r) {
  const std::size_t H = r.y.size(), S = l.S, X = l.X, M = l.M;
  const bool grid2d = l.grid2d;
  const std::vector<double>& Fs = l.F;
  const double m = o.grain.mass();
  FlightProfiles prof(H);
  std::vector<double> fine_impulse(H, 0.0);
  const int sub = std::max(1, o.profile_subdivisions);
  for (std::size_t j = 0; j < S; ++j)
    if (Fs[j] > 0 || !grid2d)
      for (int i = 0; i < sub; ++i)
        fly(o, r.y, r.u, l.vox[j], l.voy[j] + ((i + 0.5) / sub - 0.5) * o.dv, &edges, &fine_impulse,
            Fs[j] * o.dv / sub, &prof);
  r.drag.assign(H, 0.0), r.tau.assign(H, 0.0), r.dy.assign(H, 0.0);
  r.drag_resolved.assign(H, 0.0), r.number_density.assign(H, 0.0), r.number_flux.assign(H, 0.0),
      r.energy_flux.assign(H, 0.0);
  for (std::size_t k = 0; k < H; ++k) {
    const double height = r.dy[k] = std::min(edges[k + 1], 2 * r.y.back()) - edges[k];
    r.drag[k] = impulse[k] / height;
    r.tau[k] = 0.5 * (tau_edge[k] + tau_edge[k + 1]);
    r.drag_resolved[k] = fine_impulse[k] / height;
    r.number_density[k] = prof.time[k] / height;
    r.number_flux[k] = prof.number_flux[k] / height;
    r.energy_flux[k] = prof.energy_flux[k] / height;
  }
  r.u_star_eff = std::sqrt(std::max(0.0, tau_edge[0]) / o.fluid.density);
  double rate = 0, hsum = 0, lsum = 0, vxs = 0, vys = 0, airborne = 0, ahsum = 0, alsum = 0;
  r.grain_stress = 0, r.mass_flux = 0;
  for (std::size_t j = 0; j < S; ++j) {
    if (grid2d && Fs[j] <= 0) continue;
    const Trajectory& t = flights[j];
    const double w = Fs[j] * o.dv;
    r.flight_steps += t.steps, ++r.flights;
    rate += w, hsum += w * t.height, lsum += w * t.length, vxs += w * t.v_ix, vys += w * t.v_iy;
    airborne += w * t.time, ahsum += w * t.time * t.height, alsum += w * t.time * t.length;
    r.grain_stress += w * m * (t.v_ix - t.v_ox);
    r.mass_flux += w * m * t.length;
  }
  r.launch_rate = rate;
  if (rate > 0)
    r.mean_hop_height = hsum / rate, r.mean_hop_length = lsum / rate, r.mean_impact_vx = vxs / rate,
    r.mean_impact_vy = vys / rate;
  if (airborne > 0) r.airborne_hop_height = ahsum / airborne, r.airborne_hop_length = alsum / airborne;
  // The launch-weighted standard deviation of one trajectory quantity, about its mean (not from the raw
  // sums, for round-off's sake).
  auto spread = [&](double Trajectory::*field, double mean) {
    double var = 0;
    for (std::size_t j = 0; j < S && rate > 0; ++j)
      if (!grid2d || Fs[j] > 0) {
        const double dev = flights[j].*field - mean;
        var += Fs[j] * o.dv / rate * dev * dev;
      }
    return std::sqrt(var);
  };
  r.sd_hop_height = spread(&Trajectory::height, r.mean_hop_height);
  r.sd_hop_length = spread(&Trajectory::length, r.mean_hop_length);
  r.sd_impact_vx = spread(&Trajectory::v_ix, r.mean_impact_vx);
  r.sd_impact_vy = spread(&Trajectory::v_iy, r.mean_impact_vy);
  // Per v_oy bin for the tables: F summed over v_ox, its mean v_ox, and a flight at that mean.
  for (std::size_t k = 0; k < M; ++k) {
    double f = 0, fx = 0;
    for (std::size_t x = 0; x < X; ++x) f += Fs[k * X + x], fx += Fs[k * X + x] * l.vox[k * X + x];
    r.F[k] = f, r.v_ox[k] = grid2d ? (f > 0 ? fx / f : 0) : l.vox[k];
    r.trajectories[k] = grid2d ? fly(o, r.y, r.u, r.v_ox[k], r.v_launch[k]) : flights[k];
  }
  if (grid2d) r.F2d = Fs;
  r.launch_vy = launch_spread(r.v_launch, r.F);
}

}  // namespace

WindModelResult solve_wind_model(const WindModelOptions& o, const SplashKernel& splash) {
  const auto start = std::chrono::steady_clock::now();
  WindModelResult r;
  r.y = height_nodes(o);
  const std::vector<double> edges = bin_edges(r.y);
  const std::size_t H = r.y.size(), M = static_cast<std::size_t>(o.bins);
  if (!o.start.empty() && o.start.size() != static_cast<std::size_t>(o.bins))
    throw std::invalid_argument("solve_wind_model: the start has " + std::to_string(o.start.size()) +
                                " launch bins, the grid " + std::to_string(o.bins));
  const double rho = o.fluid.density, tau0 = rho * o.u_star * o.u_star, m = o.grain.mass();
  r.u_clean.resize(H);
  for (std::size_t k = 0; k < H; ++k) r.u_clean[k] = o.fluid.k * o.u_star * std::log(r.y[k] / r.y[0]);
  r.u = r.u_clean;
  r.v_launch.resize(M), r.F.assign(M, 0), r.v_ox.assign(M, 0), r.trajectories.resize(M);
  for (std::size_t j = 0; j < M; ++j) r.v_launch[j] = (j + 0.5) * o.dv;
  LaunchStates l = initial_launch_states(o, r.v_launch);
  const bool grid2d = l.grid2d;
  const std::size_t S = l.S;
  std::vector<Trajectory> flights(S);
  std::vector<double> impulse(H), tau_edge(H + 1);
  double relax = o.relaxation, last_change = 1e300;
  auto update_wind = [&](const std::vector<double>& F) {
    // Trajectories in the current wind, their drag, the stress and the new wind; returns the change of u.
    std::fill(impulse.begin(), impulse.end(), 0.0);
    for (std::size_t j = 0; j < S; ++j)
      if (!grid2d || F[j] > 0)
        flights[j] = fly(o, r.y, r.u, l.vox[j], l.voy[j], &edges, &impulse, F[j] * o.dv);
    ++r.trajectory_passes;
    if (o.drag_smoothing > 0) smooth_drag(edges, impulse, o.drag_smoothing);
    std::vector<double> u;
    wind_from_drag(o, r.y, impulse, u, tau_edge);
    const double change = max_relative_change(u, r.u);
    // The wind and the drag feed back negatively; at high flux the loop gain exceeds what a fixed
    // relaxation damps, so the relaxation halves whenever the change grows.
    if (change > last_change) relax = std::max(0.02, relax * 0.5);
    last_change = change;
    for (std::size_t k = 0; k < H; ++k) r.u[k] = relax * u[k] + (1 - relax) * r.u[k];
    return change;
  };
  FluxWatch flux;
  for (int n = 0; n < o.max_iterations; ++n) {
    double wind_change = 1;
    last_change = 1e300;
    for (int pass = 0; pass < 12 && wind_change > 0.1 * o.tolerance; ++pass) wind_change = update_wind(l.F);
    std::vector<double> vox_next;
    std::vector<double> next = splash_step(o, splash, r.v_launch, flights, l, vox_next);
    const double change = std::max(max_relative_change(next, l.F), wind_change);
    double total = 0;
    for (double x : next) total += x * o.dv;
    // The grains can carry at most the whole stress: a launch rate far beyond it means the splash replaces
    // each grain more than once however weak the wind, and no steady state exists.
    if (!std::isfinite(total) || total * m * o.u_star > 100 * tau0) {
      r.failure =
          "the flux grows without bound: this splash function replaces each grain more than once "
          "however weak the wind near the bed, so there is no steady state";
      r.iterations = n + 1;
      break;
    }
    if (flux.dying(total)) {
      r.failure = why_the_flux_died(splash, flights, l.F, r.v_launch, o);
      r.iterations = n + 1;
      break;
    }
    l.F = std::move(next), l.vox = std::move(vox_next);
    r.residuals.push_back(change);
    r.iterations = n + 1;
    if (!std::isfinite(change)) break;
    if (change < o.tolerance && n > 2) {
      r.converged = true;
      break;
    }
  }
  if (!r.converged && r.failure.empty()) r.failure = why_not_converged(r.residuals, o.tolerance);
  // Final state: trajectories and wind for the final F, then the diagnostics.
  update_wind(l.F);
  steady_state_diagnostics(o, edges, impulse, tau_edge, flights, l, r);
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

LaunchSpread launch_spread(const std::vector<double>& v, const std::vector<double>& F) {
  LaunchSpread out;
  const std::size_t n = std::min(v.size(), F.size());
  double sum = 0, first = 0, second = 0;
  std::size_t peak = 0;
  for (std::size_t k = 0; k < n; ++k) {
    sum += F[k], first += F[k] * v[k], second += F[k] * v[k] * v[k];
    if (F[k] > F[peak]) peak = k;
  }
  if (!(sum > 0)) return out;
  out.mean = first / sum;
  out.sd = std::sqrt(std::max(0.0, second / sum - out.mean * out.mean));
  const double half = 0.5 * F[peak];
  // Where F crosses `half` between bins k and k + 1.
  auto cross = [&](std::size_t k) { return v[k] + (half - F[k]) / (F[k + 1] - F[k]) * (v[k + 1] - v[k]); };
  double low = v[0], high = v[n - 1];
  for (std::size_t k = peak; k > 0; --k)
    if (F[k - 1] < half) {
      low = cross(k - 1);
      break;
    }
  for (std::size_t k = peak; k + 1 < n; ++k)
    if (F[k + 1] < half) {
      high = cross(k);
      break;
    }
  out.half_width = 0.5 * (high - low);
  return out;
}

WindBlownHops wind_blown_hops(const SplashFile& f, const WindModelOptions& o, std::size_t samples) {
  WindBlownHops out;
  out.wind = solve_wind_model(o, kernel_of(f, o));
  if (!out.wind.failure.empty())
    throw std::invalid_argument("the splash makes no steady wind at u* = " + std::to_string(o.u_star) +
                                " cm/s: " + out.wind.failure);
  const WindModelResult& w = out.wind;
  const double d = 2 * o.grain.radius, scale = std::sqrt(o.g * d);
  // Each cell's ejecta flown once (hop in d, ballistic range in d), then weighted per impact on the cell.
  std::map<const SplashCell*, std::vector<std::pair<double, double>>> flown;
  std::vector<std::pair<double, double>> weighted;  // hop, weight
  double total = 0, ballistic = 0, upstream = 0, angle_sum = 0, speed_sum = 0;
  for (std::size_t j = 0; j < w.F.size(); ++j) {
    const double rate = w.F[j] * o.dv;  // impacts per cm^2 per s of this bin's grains
    const Trajectory& t = w.trajectories[j];
    if (!(rate > 0) || !(t.v_iy < 0)) continue;
    const double speed = std::hypot(t.v_ix, t.v_iy) / scale, angle = std::atan2(-t.v_iy, t.v_ix) * 180 / M_PI;
    const SplashCell& cell = f.nearest(speed, angle);
    auto [it, fresh] = flown.try_emplace(&cell);
    if (fresh)
      for (const EjectumRow& e : cell.ejecta)
        if (e[4] > 0)
          it->second.push_back({fly(o, w.y, w.u, e[3] * scale, e[4] * scale).length / d, 2 * e[3] * e[4]});
    if (it->second.empty() || cell.impacts == 0) continue;
    const double each = rate / static_cast<double>(cell.impacts);
    for (const auto& [hop, range] : it->second) {
      weighted.push_back({hop, each});
      total += each, ballistic += each * range, upstream += hop < 0 ? each : 0;
      angle_sum += each * angle, speed_sum += each * speed;
    }
  }
  if (!(total > 0))
    throw std::invalid_argument("no impact of the steady state lands on a splash cell with recorded ejecta");
  for (const auto& [cell, hops] : flown)
    out.cells_used += hops.empty() ? 0 : 1, out.ejecta_flown += hops.size();
  out.ballistic_mean_d = ballistic / total, out.upstream_share = upstream / total;
  out.impact_deg = angle_sum / total, out.impact_speed = speed_sum / total;
  // Systematic resampling by weight: value k is the hop where the cumulative weight passes (k + 1/2) / n.
  double cumulative = 0;
  std::size_t i = 0;
  for (std::size_t k = 0; k < samples; ++k) {
    const double target = (static_cast<double>(k) + 0.5) / static_cast<double>(samples) * total;
    while (i + 1 < weighted.size() && cumulative + weighted[i].second < target)
      cumulative += weighted[i++].second;
    out.hops_d.push_back(weighted[i].first);
  }
  return out;
}

}  // namespace grainlab::saltation
