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

// The wind on a mesh geometric from the wall (first node 0.05 nu/u*, in the viscous sublayer) to the top.
class Wind {
 public:
  Wind(const FluxOptions& o, double top) : o_(o) {
    const double first = std::min(0.05 * o.viscosity / o.u_star, 0.01 * o.diameter);
    ratio_ = std::pow(top / first, 1.0 / static_cast<double>(kWindNodes - 1));
    log_ratio_ = std::log(ratio_);
    for (std::size_t k = 0; k < kWindNodes; ++k) z_.push_back(first * std::pow(ratio_, static_cast<double>(k)));
    in_ = {WindSpec::Model::VanDriest, kKappa, 0.5 * first, o.viscosity, o.u_star};
    drag_.assign(kWindNodes, 0.0), volume_.assign(kWindNodes, 0.0);
    solve(std::vector<double>(kWindNodes, 0.0), std::vector<double>(kWindNodes, 0.0));
    clean_ = u_;
  }
  // Speed at height z (log law above the top, linear in the sublayer below the first node).
  double at(double z) const {
    if (z <= z_[0]) return u_[0] * std::max(z, 0.0) / z_[0];
    if (z >= z_.back()) return u_.back() + o_.u_star / kKappa * std::log(z / z_.back());
    const double s = std::log(z / z_[0]) / log_ratio_;
    const auto k = std::min(static_cast<std::size_t>(s), kWindNodes - 2);
    const double a = (z - z_[k]) / (z_[k + 1] - z_[k]);
    return u_[k] * (1 - a) + u_[k + 1] * a;
  }
  // The cell (between nodes k and k + 1) holding height z, for the grains' drag tallies.
  std::size_t cell(double z) const {
    if (z <= z_[0]) return 0;
    return std::min(static_cast<std::size_t>(std::log(z / z_[0]) / log_ratio_), kWindNodes - 2);
  }
  // Solves the steady column for the grains' drag per cell (dyn) and solid volume per cell (cm^3), both
  // running means, over a bed area.
  void solve(const std::vector<double>& drag, const std::vector<double>& volume, double area = 1) {
    std::vector<double> stress(kWindNodes);
    double above = 0;  // tau_p / rho_f from the top down
    for (std::size_t k = kWindNodes; k-- > 0;) {
      stress[k] = o_.u_star * o_.u_star - above;
      if (k == 0) break;
      const double layer = area * (z_[k] - z_[k - 1]);
      const double phi = std::min(0.9, volume[k - 1] / layer);
      above += drag[k - 1] / (1 - phi) / (area * o_.fluid_density);
    }
    u_ = fluid::wind_profile(in_, z_, stress);
    bed_stress_ = std::max(0.0, stress[0]);
  }
  const std::vector<double>& z() const { return z_; }
  const std::vector<double>& u() const { return u_; }
  const std::vector<double>& clean() const { return clean_; }
  double bed_stress() const { return bed_stress_; }

 private:
  const FluxOptions& o_;
  fluid::WindProfileInput in_;
  double ratio_ = 1, log_ratio_ = 0, bed_stress_ = 0;
  std::vector<double> z_, u_, clean_, drag_, volume_;
};

void check(const FluxOptions& o) {
  for (double v : {o.diameter, o.grain_density, o.fluid_density, o.viscosity, o.g, o.u_star, o.length,
                   o.width, o.height, o.duration, o.dt_max, o.wind_interval, o.wind_memory})
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("every size, density, speed and time of the flux run must be positive");
  if (!(o.average_from < o.duration)) throw std::invalid_argument("average_from must be before the end");
  if (o.triggers < 1) throw std::invalid_argument("triggers must be at least 1");
}

// Mid-air collisions: grains hashed into cells one diameter wide (periodic in x and y), each pair of
// overlapping, approaching grains collided once per step.
class CollisionGrid {
 public:
  CollisionGrid(double length, double width, double d)
      : nx_(std::max(3L, static_cast<long>(length / d))), ny_(std::max(3L, static_cast<long>(width / d))),
        hx_(length / static_cast<double>(nx_)), hy_(width / static_cast<double>(ny_)), hz_(d), d_(d),
        length_(length), width_(width) {}
  std::uint64_t collide_all(Grains& g, double m, const CollisionLaw& law) {
    const std::size_t n = g.size();
    std::size_t buckets = 1;
    while (buckets < 2 * n) buckets *= 2;
    head_.assign(buckets, -1), next_.assign(n, -1), key_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const long ix = cell_index(g.x[i], hx_, nx_), iy = cell_index(g.y[i], hy_, ny_);
      const long iz = static_cast<long>(std::floor(g.z[i] / hz_));
      key_[i] = {ix, iy, iz};
      const std::size_t b = bucket(ix, iy, iz, buckets);
      next_[i] = head_[b], head_[b] = static_cast<long>(i);
    }
    std::uint64_t hits = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (long dx = -1; dx <= 1; ++dx)
        for (long dy = -1; dy <= 1; ++dy)
          for (long dz = -1; dz <= 1; ++dz) {
            const long cx = wrap(key_[i][0] + dx, nx_), cy = wrap(key_[i][1] + dy, ny_), cz = key_[i][2] + dz;
            for (long j = head_[bucket(cx, cy, cz, buckets)]; j >= 0; j = next_[j]) {
              const auto u = static_cast<std::size_t>(j);
              if (u <= i || key_[u][0] != cx || key_[u][1] != cy || key_[u][2] != cz) continue;
              hits += pair(g, i, u, m, law);
            }
          }
    return hits;
  }

 private:
  static long wrap(long i, long n) { return ((i % n) + n) % n; }
  static long cell_index(double x, double h, long n) { return wrap(static_cast<long>(std::floor(x / h)), n); }
  static std::size_t bucket(long x, long y, long z, std::size_t buckets) {
    const auto h = static_cast<std::uint64_t>(x) * 73856093u ^ static_cast<std::uint64_t>(y) * 19349663u ^
                   static_cast<std::uint64_t>(z) * 83492791u;
    return static_cast<std::size_t>(h & (buckets - 1));
  }
  bool pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) const {
    double dx = g.x[j] - g.x[i], dy = g.y[j] - g.y[i];
    dx -= length_ * std::round(dx / length_), dy -= width_ * std::round(dy / width_);
    const double dz = g.z[j] - g.z[i], r2 = dx * dx + dy * dy + dz * dz;
    if (r2 >= d_ * d_ || r2 <= 0) return false;
    Vec3 v1{g.vx[i], g.vy[i], g.vz[i]}, v2{g.vx[j], g.vy[j], g.vz[j]};
    if (!collide(v1, v2, m, m, Vec3{dx, dy, dz} / std::sqrt(r2), law)) return false;
    g.vx[i] = v1.x(), g.vy[i] = v1.y(), g.vz[i] = v1.z(), g.vx[j] = v2.x(), g.vy[j] = v2.y(), g.vz[j] = v2.z();
    return true;
  }
  long nx_, ny_;
  double hx_, hy_, hz_, d_, length_, width_;
  std::vector<long> head_, next_;
  std::vector<std::array<long, 3>> key_;
};

}  // namespace

double flux_law(double shields, double shields_threshold, double kappa, double mu_b, double c_m) {
  const double excess = std::max(0.0, shields - shields_threshold);
  return 2 * std::sqrt(shields_threshold) / (kappa * mu_b) * excess * (1 + c_m / mu_b * excess);
}

FluxResult run_flux(const FluxOptions& o) {
  check(o);
  const auto start = std::chrono::steady_clock::now();
  const LammelParameters splash = LammelParameters::named(o.splash);
  const double d = o.diameter, s = o.grain_density / o.fluid_density, g_hat = (1 - 1 / s) * o.g;
  const double t_unit = std::sqrt(d / g_hat), length = o.length * d, width = o.width * d, area = length * width;
  const double m = o.grain_density * M_PI / 6 * d * d * d, volume = M_PI / 6 * d * d * d;
  const FluidSpec fluid{o.fluid_density, o.viscosity, o.grain_density};
  const LammelCoefficients coefficients = lammel_coefficients(splash, d, d);
  const double e_d2 = m * o.g * d;
  FluxResult r;
  r.s = s, r.galileo = std::sqrt(s * g_hat * d * d * d) / o.viscosity;
  r.shields = o.fluid_density * o.u_star * o.u_star / (o.grain_density * g_hat * d);

  Wind wind(o, o.height * d);
  std::vector<double> drag_mean(kWindNodes, 0.0), volume_mean(kWindNodes, 0.0);
  std::vector<double> drag_now(kWindNodes, 0.0), volume_now(kWindNodes, 0.0);
  Rng rng(o.seed);
  Grains grains;
  for (int k = 0; k < o.triggers; ++k)
    grains.add(rng.uniform(0, length), rng.uniform(0, width), d, 0, 0, 20 * std::sqrt(o.g * d));
  CollisionGrid grid(length, width, d);
  const CollisionLaw law{o.collision_restitution, o.collision_friction};

  // Acceleration of a grain at height z moving at v: drag of the huo2021 law and buoyant gravity.
  auto accel = [&](double z, double vx, double vy, double vz, double& ax, double& ay, double& az) {
    const double rx = vx - wind.at(z), speed = std::sqrt(rx * rx + vy * vy + vz * vz);
    const double c = fluid::drag_rate(WindSpec::DragLaw::Huo2021, fluid, d, speed);
    ax = -c * rx, ay = -c * vy, az = -c * vz - g_hat;
    return -c * rx;  // the drag the wind gives per unit grain mass, x
  };

  double t = 0, next_wind = o.wind_interval * t_unit, next_sample = 0, q_sum = 0, q_sum2 = 0, air_sum = 0;
  double impact_speed_sum = 0, impact_angle_sum = 0, window_impacts = 0, since_wind = 0;
  std::size_t samples = 0;
  const double t_end = o.duration * t_unit, t_avg = o.average_from * t_unit;
  while (t < t_end) {
    double vmax = 0;
    for (std::size_t i = 0; i < grains.size(); ++i)
      vmax = std::max(vmax, std::abs(grains.vx[i]) + std::abs(grains.vy[i]) + std::abs(grains.vz[i]));
    const double dt = std::min(o.dt_max * std::sqrt(d / o.g), vmax > 0 ? 0.2 * d / vmax : 1e300);
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
      grains.x[i] -= length * std::floor(grains.x[i] / length), grains.y[i] -= width * std::floor(grains.y[i] / width);
      const std::size_t k = wind.cell(grains.z[i]);
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
      } else {
        grains.remove(i);  // dead: it stays in the bed
      }
      const EjectaLaw ejecta = ejecta_law(splash, e_bar, 0.5 * m * speed * speed, e_d2);
      const int count = sample_ejecta_count(ejecta, rng);
      for (int k = 0; k < count; ++k) {
        const double v = std::sqrt(2 * sample_ejectum_energy(ejecta, rng) / m);
        if (v * v <= 2 * g_hat * d) continue;  // cannot rise a diameter: it stays
        const double rho = d * std::sqrt(rng.uniform()), phi = 2 * M_PI * rng.uniform();
        double x = px + rho * std::cos(phi), y = py + rho * std::sin(phi);
        x -= length * std::floor(x / length), y -= width * std::floor(y / width);
        grains.add(x, y, 0.5 * d, 0, 0, v);
      }
    }
    t += dt, since_wind += dt;
    if (t >= next_wind) {  // the drag's running mean over wind_memory, then the steady column
      const double a = std::min(1.0, since_wind / (o.wind_memory * t_unit));
      for (std::size_t k = 0; k < kWindNodes; ++k) {
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
