#include "flux_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "collision.hpp"
#include "fluid.hpp"
#include "rng.hpp"

namespace grainlab::ripples::hybrid {

namespace {

constexpr double kKappa = 0.42;
constexpr std::size_t kWindNodes = 240;

// Airborne grains, structure of arrays.
struct Grains {
  std::vector<double> x, y, z, vx, vy, vz;
  std::size_t size() const { return x.size(); }
  void add(double px, double py, double pz, double ux, double uy, double uz) {
    x.push_back(px), y.push_back(py), z.push_back(pz), vx.push_back(ux), vy.push_back(uy), vz.push_back(uz);
  }
  void remove(std::size_t i) {  // swap with the last
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz}) (*v)[i] = v->back(), v->pop_back();
  }
};

// The wind: solved on a mesh geometric from the wall (first node in the viscous sublayer) to the top, and
// looked up by the grains in a table uniform in height (no logarithm per grain); the grains' drag and volume
// are tallied in the table's bins and handed to the mesh's cells at each update.
class Wind {
 public:
  Wind(const FluxOptions& o, double top) : o_(o), top_(top) {
    const double first = std::min(0.05 * o.viscosity / o.u_star, 0.01 * o.diameter);
    const double ratio = std::pow(top / first, 1.0 / static_cast<double>(kWindNodes - 1));
    for (std::size_t k = 0; k < kWindNodes; ++k)
      z_.push_back(first * std::pow(ratio, static_cast<double>(k)));
    in_ = {WindSpec::Model::VanDriest, kKappa, 0.0, o.viscosity, o.u_star};  // smooth wall, u(0) = 0
    h_ = kBinHeight * o.diameter;
    bins_ = static_cast<std::size_t>(std::ceil(top / h_)) + 1;
    inv_h_ = 1 / h_;
    std::vector<double> none(bins_, 0.0);
    solve(none, none, 1);
    clean_ = u_;
  }
  std::size_t bins() const { return bins_; }
  // The table's bin at height z (the top bin takes everything above).
  std::size_t bin(double z) const {
    const double s = std::max(z, 0.0) * inv_h_;
    return s < static_cast<double>(bins_ - 1) ? static_cast<std::size_t>(s) : bins_ - 1;
  }
  double at(double z) const {
    const double s = std::max(z, 0.0) * inv_h_;
    if (s >= static_cast<double>(bins_ - 1)) return table_.back() + o_.u_star / kKappa * std::log(z / top_);
    const auto k = static_cast<std::size_t>(s);
    const double a = s - static_cast<double>(k);
    return table_[k] + a * (table_[k + 1] - table_[k]);
  }
  // Solves the steady column for the grains' drag (dyn) and solid volume (cm^3) per table bin, over the
  // bed area: each node's stress is u*^2 less the drag above it, over 1 - phi.
  void solve(const std::vector<double>& drag, const std::vector<double>& volume, double area) {
    std::vector<double> cell_drag(kWindNodes, 0.0), cell_volume(kWindNodes, 0.0);
    for (std::size_t b = 0; b < bins_; ++b) {
      const double zc = (static_cast<double>(b) + 0.5) * h_;
      const auto k = static_cast<std::size_t>(std::lower_bound(z_.begin(), z_.end(), zc) - z_.begin());
      const std::size_t cell =
          std::clamp<std::size_t>(k, 1, kWindNodes - 1) - 1;  // between nodes cell, cell+1
      cell_drag[cell] += drag[b], cell_volume[cell] += volume[b];
    }
    std::vector<double> stress(kWindNodes);
    double above = 0;  // tau_p / rho_f from the top down
    for (std::size_t k = kWindNodes; k-- > 0;) {
      stress[k] = o_.u_star * o_.u_star - above;
      if (k == 0) break;
      const double phi = std::min(0.9, cell_volume[k - 1] / (area * (z_[k] - z_[k - 1])));
      above += cell_drag[k - 1] / (1 - phi) / (area * o_.fluid_density);
    }
    u_ = fluid::wind_profile(in_, z_, stress);
    bed_stress_ = std::max(0.0, stress[0]);
    table_.resize(bins_);
    for (std::size_t b = 0; b < bins_; ++b) table_[b] = mesh_at(static_cast<double>(b) * h_);
  }
  const std::vector<double>& z() const { return z_; }
  const std::vector<double>& u() const { return u_; }
  const std::vector<double>& clean() const { return clean_; }
  double bed_stress() const { return bed_stress_; }

 private:
  static constexpr double kBinHeight = 0.1;  // diameters; grain centres never come below 0.5
  double mesh_at(double z) const {
    if (z <= z_[0]) return u_[0] * std::max(z, 0.0) / z_[0];
    if (z >= z_.back()) return u_.back();
    const auto k = static_cast<std::size_t>(std::upper_bound(z_.begin(), z_.end(), z) - z_.begin()) - 1;
    const double a = (z - z_[k]) / (z_[k + 1] - z_[k]);
    return u_[k] * (1 - a) + u_[k + 1] * a;
  }
  const FluxOptions& o_;
  fluid::WindProfileInput in_;
  double top_, h_ = 1, inv_h_ = 1, bed_stress_ = 0;
  std::size_t bins_ = 0;
  std::vector<double> z_, u_, clean_, table_;
};

// x taken into [0, period) (a grain moves far less than a period per step).
double into(double x, double period) {
  return x < 0 ? x + period : (x >= period ? x - period : x);
}

void check(const FluxOptions& o) {
  for (double v : {o.diameter, o.grain_density, o.fluid_density, o.viscosity, o.g, o.u_star, o.length,
                   o.width, o.height, o.duration, o.dt_max, o.wind_interval, o.wind_memory})
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("every size, density, speed and time of the flux run must be positive");
  if (!(o.average_from < o.duration)) throw std::invalid_argument("average_from must be before the end");
  if (o.triggers < 1) throw std::invalid_argument("triggers must be at least 1");
}

// Mid-air collisions: grains sorted into vertical columns one diameter square (periodic in x and y; a
// counting sort, so the cost is linear), each grain checked against the rest of its column and the four
// columns ahead of it, each pair of overlapping, approaching grains collided once per step. Saltation is
// dilute, so a column holds a grain or two and the z test rejects most of them.
class CollisionGrid {
 public:
  CollisionGrid(double length, double width, double d)
      : nx_(std::max(3L, static_cast<long>(length / d))),
        ny_(std::max(3L, static_cast<long>(width / d))),
        inv_hx_(static_cast<double>(nx_) / length),
        inv_hy_(static_cast<double>(ny_) / width),
        d_(d),
        length_(length),
        width_(width) {}
  std::uint64_t collide_all(Grains& g, double m, const CollisionLaw& law) {
    const std::size_t n = g.size(), columns = static_cast<std::size_t>(nx_ * ny_);
    start_.assign(columns + 1, 0), column_.resize(n), order_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const long ix = std::min(nx_ - 1, static_cast<long>(g.x[i] * inv_hx_));
      const long iy = std::min(ny_ - 1, static_cast<long>(g.y[i] * inv_hy_));
      column_[i] = static_cast<std::uint32_t>(ix * ny_ + iy);
      ++start_[column_[i] + 1];
    }
    for (std::size_t c = 0; c < columns; ++c) start_[c + 1] += start_[c];
    fill_ = start_;
    for (std::size_t i = 0; i < n; ++i) order_[fill_[column_[i]]++] = static_cast<std::uint32_t>(i);
    std::uint64_t hits = 0;
    static constexpr long kAhead[4][2] = {{1, -1}, {1, 0}, {1, 1}, {0, 1}};
    // By grain, not by column: most columns are empty.
    for (std::uint32_t a = 0; a < n; ++a) {
      const std::uint32_t i = order_[a], c = column_[i];
      const long ix = static_cast<long>(c) / ny_, iy = static_cast<long>(c) % ny_;
      for (std::uint32_t b = a + 1; b < start_[c + 1]; ++b) hits += pair(g, i, order_[b], m, law);
      for (const auto& off : kAhead) {
        const auto o = static_cast<std::size_t>(wrap(ix + off[0], nx_) * ny_ + wrap(iy + off[1], ny_));
        for (std::uint32_t b = start_[o]; b < start_[o + 1]; ++b) hits += pair(g, i, order_[b], m, law);
      }
    }
    return hits;
  }

 private:
  static long wrap(long i, long n) { return i < 0 ? i + n : (i >= n ? i - n : i); }
  // The nearest periodic image of a separation (both grains inside the box).
  static double nearest(double s, double period) {
    return s > 0.5 * period ? s - period : (s < -0.5 * period ? s + period : s);
  }
  bool pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) const {
    const double dz = g.z[j] - g.z[i];
    if (dz >= d_ || dz <= -d_) return false;
    const double dx = nearest(g.x[j] - g.x[i], length_), dy = nearest(g.y[j] - g.y[i], width_);
    const double r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= d_ * d_ || r2 <= 0) return false;
    Vec3 v1{g.vx[i], g.vy[i], g.vz[i]}, v2{g.vx[j], g.vy[j], g.vz[j]};
    if (!collide(v1, v2, m, m, Vec3{dx, dy, dz} / std::sqrt(r2), law)) return false;
    g.vx[i] = v1.x(), g.vy[i] = v1.y(), g.vz[i] = v1.z(), g.vx[j] = v2.x(), g.vy[j] = v2.y(),
    g.vz[j] = v2.z();
    return true;
  }
  long nx_, ny_;
  double inv_hx_, inv_hy_, d_, length_, width_;
  std::vector<std::uint32_t> start_, fill_, column_, order_;
};

}  // namespace

WindColumn clean_wind(const FluxOptions& o) {
  check(o);
  const Wind wind(o, o.height * o.diameter);
  return {wind.z(), wind.clean()};
}

double flux_law(double shields, double shields_threshold, double kappa, double mu_b, double c_m) {
  const double excess = std::max(0.0, shields - shields_threshold);
  return 2 * std::sqrt(shields_threshold) / (kappa * mu_b) * excess * (1 + c_m / mu_b * excess);
}

FluxResult run_flux(const FluxOptions& o) {
  check(o);
  const auto start = std::chrono::steady_clock::now();
  const LammelParameters splash = LammelParameters::named(o.splash);
  const double d = o.diameter, s = o.grain_density / o.fluid_density, g_hat = (1 - 1 / s) * o.g;
  const double t_unit = std::sqrt(d / g_hat), length = o.length * d, width = o.width * d,
               area = length * width;
  const double m = o.grain_density * M_PI / 6 * d * d * d, volume = M_PI / 6 * d * d * d;
  const LammelCoefficients coefficients = lammel_coefficients(splash, d, d);
  const double e_d2 = m * o.g * d;
  FluxResult r;
  r.s = s, r.galileo = std::sqrt(s * g_hat * d * d * d) / o.viscosity;
  r.shields = o.fluid_density * o.u_star * o.u_star / (o.grain_density * g_hat * d);

  Wind wind(o, o.height * d);
  std::vector<double> drag_mean(wind.bins(), 0.0), volume_mean(wind.bins(), 0.0);
  std::vector<double> drag_now(wind.bins(), 0.0), volume_now(wind.bins(), 0.0);
  Rng rng(o.seed);
  Grains grains;
  for (int k = 0; k < o.triggers; ++k)
    grains.add(rng.uniform(0, length), rng.uniform(0, width), d, 0, 0, 20 * std::sqrt(o.g * d));
  CollisionGrid grid(length, width, d);
  const CollisionLaw law{o.collision_restitution, o.collision_friction};

  // Acceleration of a grain at height z moving at v: drag of the huo2021 law and buoyant gravity. The
  // law written out for the hot loop: c = 3/4 (rho_f / (rho_p d)) C_d |v| and C_d |v| = (sqrt(|v| / 2) +
  // sqrt(24 nu / d))^2 (fluid::drag_rate's huo2021, tested equal).
  const double drag_a = 0.75 * o.fluid_density / (o.grain_density * d),
               drag_b = std::sqrt(24 * o.viscosity / d);
  auto accel = [&](double z, double vx, double vy, double vz, double& ax, double& ay, double& az) {
    const double rx = vx - wind.at(z), speed = std::sqrt(rx * rx + vy * vy + vz * vz);
    const double root = std::sqrt(0.5 * speed) + drag_b, c = drag_a * root * root;
    ax = -c * rx, ay = -c * vy, az = -c * vz - g_hat;
    return -c * rx;  // the drag the wind gives per unit grain mass, x
  };

  double t = 0, next_wind = o.wind_interval * t_unit, next_sample = 0, q_sum = 0, q_sum2 = 0, air_sum = 0;
  double v2_next = 0, v2_launch = 0;
  for (std::size_t i = 0; i < grains.size(); ++i)
    v2_launch = std::max(v2_launch, grains.vz[i] * grains.vz[i]);
  double impact_speed_sum = 0, impact_angle_sum = 0, window_impacts = 0, since_wind = 0;
  std::size_t samples = 0;
  const double t_end = o.duration * t_unit, t_avg = o.average_from * t_unit;
  while (t < t_end) {
    // The largest speed of the last step's grains (and of any launched since, by the splash's bound).
    const double v2max = std::max(v2_next, v2_launch);
    v2_next = 0, v2_launch = 0;
    const double dt = std::min(o.dt_max * std::sqrt(d / o.g), v2max > 0 ? 0.2 * d / std::sqrt(v2max) : 1e300);
    // Heun steps with the wind frozen; the drag the grains took is tallied for the wind.
    for (std::size_t i = 0; i < grains.size(); ++i) {
      double ax, ay, az, bx, by, bz;
      const double f1 = accel(grains.z[i], grains.vx[i], grains.vy[i], grains.vz[i], ax, ay, az);
      const double wx = grains.vx[i] + dt * ax, wy = grains.vy[i] + dt * ay, wz = grains.vz[i] + dt * az;
      const double z1 = grains.z[i] + dt * grains.vz[i];
      const double f2 = accel(z1, wx, wy, wz, bx, by, bz);
      grains.x[i] += 0.5 * dt * (grains.vx[i] + wx), grains.y[i] += 0.5 * dt * (grains.vy[i] + wy);
      grains.z[i] += 0.5 * dt * (grains.vz[i] + wz);
      grains.vx[i] += 0.5 * dt * (ax + bx), grains.vy[i] += 0.5 * dt * (ay + by);
      grains.vz[i] += 0.5 * dt * (az + bz);
      grains.x[i] = into(grains.x[i], length), grains.y[i] = into(grains.y[i], width);
      v2_next = std::max(
          v2_next, grains.vx[i] * grains.vx[i] + grains.vy[i] * grains.vy[i] + grains.vz[i] * grains.vz[i]);
      const std::size_t k = wind.bin(grains.z[i]);
      drag_now[k] += m * 0.5 * (f1 + f2) * dt, volume_now[k] += volume * dt;
    }
    r.grain_steps += grains.size(), ++r.steps;
    if (o.collisions) r.collisions += grid.collide_all(grains, m, law);
    // Impacts: a grain whose bottom reaches the bed while descending rebounds or dies, and ejects.
    const bool in_window = t >= t_avg;
    for (std::size_t i = grains.size(); i-- > 0;) {
      if (grains.z[i] > 0.5 * d || grains.vz[i] >= 0) continue;
      const double vh = std::hypot(grains.vx[i], grains.vy[i]), speed = std::hypot(vh, grains.vz[i]);
      const double theta = std::atan2(-grains.vz[i], vh);
      const double ex = vh > 0 ? grains.vx[i] / vh : 1, ey = vh > 0 ? grains.vy[i] / vh : 0;
      const double px = grains.x[i], py = grains.y[i];
      if (in_window) impact_speed_sum += speed, impact_angle_sum += theta, ++window_impacts;
      const double e_bar = std::max(0.0, mean_restitution(coefficients, d, d, theta));
      const double up = rebound_angle(coefficients, theta, rng.uniform()), rebound = e_bar * speed;
      const double rz = rebound * std::sin(up);
      if (up > 0 && rz * rz > 2 * g_hat * d) {
        grains.z[i] = 0.5 * d, grains.vx[i] = rebound * std::cos(up) * ex;
        grains.vy[i] = rebound * std::cos(up) * ey, grains.vz[i] = rz;
        v2_launch = std::max(v2_launch, rebound * rebound);
      } else {
        grains.remove(i);  // dead: it stays in the bed
      }
      const EjectaLaw ejecta = ejecta_law(splash, e_bar, 0.5 * m * speed * speed, e_d2);
      const int count = sample_ejecta_count(ejecta, rng);
      for (int k = 0; k < count; ++k) {
        const double v = std::sqrt(2 * sample_ejectum_energy(ejecta, rng) / m);
        if (v * v <= 2 * g_hat * d) continue;  // cannot rise a diameter: it stays
        const double rho = d * std::sqrt(rng.uniform()), phi = 2 * M_PI * rng.uniform();
        const double x = px + rho * std::cos(phi), y = py + rho * std::sin(phi);
        grains.add(into(x, length), into(y, width), 0.5 * d, 0, 0, v);
        v2_launch = std::max(v2_launch, v * v);
      }
    }
    t += dt, since_wind += dt;
    if (t >= next_wind) {  // the drag's running mean over wind_memory, then the steady column
      const double a = std::min(1.0, since_wind / (o.wind_memory * t_unit));
      for (std::size_t k = 0; k < wind.bins(); ++k) {
        drag_mean[k] += a * (drag_now[k] / since_wind - drag_mean[k]);
        volume_mean[k] += a * (volume_now[k] / since_wind - volume_mean[k]);
      }
      std::fill(drag_now.begin(), drag_now.end(), 0.0), std::fill(volume_now.begin(), volume_now.end(), 0.0);
      wind.solve(drag_mean, volume_mean, area);
      next_wind = t + o.wind_interval * t_unit, since_wind = 0;
    }
    if (t >= next_sample) {
      double q = 0;
      for (std::size_t i = 0; i < grains.size(); ++i) q += m * grains.vx[i];
      q /= area;
      const double q_star = q / (o.grain_density * d * std::sqrt(s * g_hat * d));
      r.series.push_back({t / t_unit, q_star, static_cast<double>(grains.size())});
      if (in_window) q_sum += q, q_sum2 += q * q, air_sum += static_cast<double>(grains.size()), ++samples;
      if (o.progress) o.progress(t / t_unit, o.duration);
      next_sample += t_unit;
    }
    if (grains.size() == 0) break;  // transport died
  }
  if (samples > 0) {
    const double n = static_cast<double>(samples);
    r.mass_flux = q_sum / n, r.airborne = air_sum / n;
    r.mass_flux_sd = std::sqrt(std::max(0.0, q_sum2 / n - r.mass_flux * r.mass_flux));
    r.mass_flux_star = r.mass_flux / (o.grain_density * d * std::sqrt(s * g_hat * d));
  }
  if (window_impacts > 0) {
    r.mean_impact_speed = impact_speed_sum / window_impacts;
    r.mean_impact_angle_deg = impact_angle_sum / window_impacts * 180 / M_PI;
    r.impacts_per_area_time = window_impacts / (area * std::max(t - t_avg, 1e-300));
  }
  r.u_star_bed = std::sqrt(wind.bed_stress());
  r.z = wind.z(), r.u = wind.u(), r.u_clean = wind.clean();
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace grainlab::ripples::hybrid
