#include "wind.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "fluid.hpp"
#include "input_error.hpp"
#include "parallel.hpp"

namespace grainlab::dem {

namespace {
double median_radius(const Particles& p, std::size_t n) {
  std::vector<double> r(p.r.begin(), p.r.begin() + static_cast<long>(n));
  if (r.empty()) return 1;
  std::nth_element(r.begin(), r.begin() + static_cast<long>(r.size() / 2), r.end());
  return r[r.size() / 2];
}

constexpr double kBedMemory = 0.01;  // s: the bed level is a running mean over this time
}  // namespace

WindField::WindField(const Scene& scene, const Particles& p, std::size_t n)
    : w_(scene.wind), f_(scene.fluid) {
  if (w_.model != WindSpec::Model::Fixed && !scene.periodic_x)
    throw InputError({scene.path, 0}, "wind.model",
                     "a wind with grain feedback needs [scene] periodic_x: the grains' drag is averaged over "
                     "the periodic width (or use model = \"fixed\")");
  if (n == 0) throw InputError({scene.path, 0}, "effects", "wind_drag needs grains to blow on");
  const double r = median_radius(p, n);
  diameter_ = 2 * r;
  if (w_.roughness <= 0) w_.roughness = diameter_ / 30;
  if (w_.bin_height <= 0) w_.bin_height = r;
  if (w_.top <= 0) w_.top = 400 * diameter_;
  thickness_ = w_.thickness > 0 ? w_.thickness : diameter_;
  width_ = scene.periodic_x ? scene.periodic_x->second - scene.periodic_x->first : 1.0;
  dy_ = w_.bin_height;
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < n; ++i) lo = std::min(lo, p.y[i] - p.r[i]), hi = std::max(hi, p.y[i] + p.r[i]);
  y_lo_ = w_.bed_level ? std::min(lo, *w_.bed_level - dy_) : lo;
  cells_ = static_cast<std::size_t>(std::ceil((hi - lo + w_.top) / dy_));
  // Tally units: 1e-7 of what a median grain moving at u* through still air gives in one step of
  // 1e-6 s, so a grain-step is resolved to 1e-7 and even 1e6 grains over 1e4 steps cannot overflow.
  const double m = f_.grain_density * 4.0 / 3.0 * M_PI * r * r * r;
  const double speed = std::max(w_.u_star, 1.0);
  unit_a_ = m * fluid::drag_rate(w_.drag_law, f_, diameter_, speed) * 1e-6 * 1e-7;
  unit_b_ = unit_a_ * speed;
  tally_a_.assign(cells_, 0), tally_b_.assign(cells_, 0), tally_applied_.assign(cells_, 0);
  std::vector<std::uint64_t> counts(cells_, 0);
  for (std::size_t i = 0; i < n; ++i) ++counts[cell_of(p.y[i])];
  snap_.bed_level = w_.bed_level ? *w_.bed_level : find_bed_level(counts);
  snap_.y.resize(cells_);
  for (std::size_t k = 0; k < cells_; ++k) snap_.y[k] = y_lo_ + (static_cast<double>(k) + 0.5) * dy_;
  snap_.grain_stress.assign(cells_, 0.0);
  const fluid::WindProfileInput in{w_.model, w_.kappa, w_.roughness, f_.viscosity, w_.u_star};
  snap_.u_clean =
      fluid::wind_profile(in, heights_above_bed(), std::vector<double>(cells_, w_.u_star * w_.u_star));
  snap_.u = snap_.u_clean;
  snap_.u_star_eff = w_.u_star;
  next_update_ = w_.update_interval;
}

std::vector<double> WindField::heights_above_bed() const {
  std::vector<double> z(cells_);
  for (std::size_t k = 0; k < cells_; ++k) z[k] = snap_.y[k] - snap_.bed_level;
  return z;
}

std::size_t WindField::cell_of(double y) const {
  const double k = std::floor((y - y_lo_) / dy_);
  return static_cast<std::size_t>(std::clamp(k, 0.0, static_cast<double>(cells_ - 1)));
}

WindField::Stencil WindField::stencil_of(double y) const {
  const double s = (y - y_lo_) / dy_ - 0.5;  // in cell-centre units
  if (s <= 0) return {0, 0.0};
  if (s >= static_cast<double>(cells_ - 1)) return {static_cast<std::uint32_t>(cells_ - 2), 1.0};
  const auto k = static_cast<std::size_t>(s);
  return {static_cast<std::uint32_t>(k), s - static_cast<double>(k)};
}

double WindField::u_at(double y) const {
  const Stencil st = stencil_of(y);
  if (st.upper == 1.0 && y > snap_.y[cells_ - 1]) {  // above the column: the clean log law continues
    const double z_top = snap_.y[cells_ - 1] - snap_.bed_level, z = y - snap_.bed_level;
    return snap_.u[cells_ - 1] + w_.u_star / w_.kappa * std::log(z / z_top);
  }
  return snap_.u[st.cell] * (1 - st.upper) + snap_.u[st.cell + 1] * st.upper;
}

void WindField::add_drag(Particles& p, std::size_t n) {
  rate_.resize(n), rate_v_.resize(n), drag_x_.resize(n), stencil_.resize(n);
  const double buried = snap_.bed_level;
  for (std::size_t i = 0; i < n; ++i) {
    // A grain wholly below the bed level sits in still pore air: its drag (from its own creeping speed) is
    // negligible beside its contacts, and skipping it keeps the cost with the surface and the air.
    if (p.y[i] + p.r[i] < buried) {
      rate_[i] = 0;
      continue;
    }
    stencil_[i] = stencil_of(p.y[i]);
    const double rx = p.vx[i] - u_at(p.y[i]), ry = p.vy[i];
    // The drag rate of the sphere the disc stands for, times the disc's own mass.
    const double mc = p.m[i] * fluid::drag_rate(w_.drag_law, f_, 2 * p.r[i], std::hypot(rx, ry));
    p.fx[i] -= mc * rx;
    p.fy[i] -= mc * ry;
    rate_[i] = mc, rate_v_[i] = mc * p.vx[i], drag_x_[i] = -mc * rx;
  }
}

void WindField::after_step(const Particles& p, std::size_t n, double t, double dt, bool distributed) {
  // Each grain's drag goes to the two cells its wind was interpolated from, with the same weights, so
  // the column's linearised sink is the grains' drag up to the lumping of the weights (without this the
  // bed's dense top cell was charged for the wind of the cell above and the deferred correction diverged).
  const double sa = dt / unit_a_, sb = dt / unit_b_;
  auto add = [](std::vector<std::int64_t>& tally, std::size_t k, double upper, double amount) {
    tally[k] += std::llround(amount * (1 - upper));
    tally[k + 1] += std::llround(amount * upper);
  };
  for (std::size_t i = 0; i < n && i < rate_.size(); ++i)
    if (rate_[i] != 0) {
      const auto [k, upper] = stencil_[i];
      add(tally_a_, k, upper, rate_[i] * sa);
      add(tally_b_, k, upper, rate_v_[i] * sb);
      add(tally_applied_, k, upper, drag_x_[i] * sb);
    }
  if (t >= next_update_ * (1 - 1e-12)) update(p, n, t, distributed);
}

double WindField::find_bed_level(const std::vector<std::uint64_t>& counts) const {
  // The bed surface: where the number of grain centres per two cells (one diameter at the default cell
  // height) falls below half its largest value, scanning down from the top, interpolated in the cell.
  std::vector<double> c(counts.size(), 0.0);
  for (std::size_t k = 0; k < counts.size(); ++k)
    c[k] = static_cast<double>(counts[k] + (k + 1 < counts.size() ? counts[k + 1] : 0));
  const double half = 0.5 * *std::max_element(c.begin(), c.end());
  for (std::size_t k = c.size(); k-- > 1;)
    if (c[k - 1] >= half) {
      const double a = c[k - 1] > c[k] ? (c[k - 1] - half) / (c[k - 1] - c[k]) : 0.0;
      return y_lo_ + (static_cast<double>(k) + std::clamp(a, 0.0, 1.0)) * dy_;
    }
  return y_lo_;
}

void WindField::update(const Particles& p, std::size_t n, double t, bool distributed) {
  // Two's complement: the signed sums survive the unsigned collective exactly.
  std::vector<std::uint64_t> sums(3 * cells_), counts(cells_, 0);
  for (std::size_t k = 0; k < cells_; ++k)
    sums[k] = static_cast<std::uint64_t>(tally_a_[k]),
    sums[cells_ + k] = static_cast<std::uint64_t>(tally_b_[k]),
    sums[2 * cells_ + k] = static_cast<std::uint64_t>(tally_applied_[k]);
  for (std::size_t i = 0; i < n; ++i) ++counts[cell_of(p.y[i])];
  if (distributed) parallel::sum_all(sums), parallel::sum_all(counts);
  const double interval = t - last_update_;
  if (!w_.bed_level)
    snap_.bed_level += std::min(1.0, interval / kBedMemory) * (find_bed_level(counts) - snap_.bed_level);
  const std::vector<double> z = heights_above_bed();
  const fluid::WindProfileInput in{w_.model, w_.kappa, w_.roughness, f_.viscosity, w_.u_star};
  // Time-integrated drag (m c dt, m c v dt) per cell, as rates per fluid mass of the cell: the sink is
  // a u - b.
  std::vector<double> A(cells_), B(cells_), applied(cells_), a(cells_), b(cells_);
  const double fluid_mass = f_.density * bed_area() * dy_;
  auto tally = [&](std::size_t at) { return static_cast<double>(static_cast<std::int64_t>(sums[at])); };
  for (std::size_t k = 0; k < cells_; ++k) {
    A[k] = tally(k) * unit_a_, B[k] = tally(cells_ + k) * unit_b_,
    applied[k] = tally(2 * cells_ + k) * unit_b_;
    a[k] = A[k] / (interval * fluid_mass), b[k] = B[k] / (interval * fluid_mass);
  }
  if (w_.model != WindSpec::Model::Fixed) {
    if (w_.inertia) {
      snap_.u = fluid::advance_wind_column(in, dy_, z, snap_.u, a, b, interval, eddy_);
    } else {
      // The steady column for this drag; the eddy viscosity depends on u, so a few fixed-point passes.
      const double steady = std::numeric_limits<double>::infinity();
      for (int pass = 0; pass < 3; ++pass)
        snap_.u = fluid::advance_wind_column(in, dy_, z, snap_.u, a, b, steady, eddy_);
    }
  }
  snap_.u_clean = fluid::wind_profile(in, z, std::vector<double>(cells_, w_.u_star * w_.u_star));
  if (w_.model == WindSpec::Model::Fixed) snap_.u = snap_.u_clean;
  // What the wind gave the grains over the interval at its new speeds, summed from the top, and what the
  // grains felt (at the speeds of the previous update).
  double above = 0, given = 0;
  for (std::size_t k = cells_; k-- > 0;) {
    above += A[k] * snap_.u[k] - B[k];
    snap_.grain_stress[k] = above / (interval * bed_area());
    given += applied[k];
  }
  snap_.drag_per_area = snap_.grain_stress[0];
  snap_.applied_per_area = given / (interval * bed_area());

  const std::size_t kb = std::min(cells_ - 2, cell_of(snap_.bed_level + diameter_));
  const double tau_f = fluid::face_stress(in, dy_, z, snap_.u, kb), tau0 = w_.u_star * w_.u_star;
  snap_.u_star_eff = std::sqrt(std::max(0.0, tau_f));
  if (tau0 > 0)
    snap_.stress_partition = (f_.density * tau_f + snap_.grain_stress[kb + 1]) / (f_.density * tau0);
  snap_.time = t;
  ++snap_.updates;
  std::fill(tally_a_.begin(), tally_a_.end(), 0);
  std::fill(tally_b_.begin(), tally_b_.end(), 0);
  std::fill(tally_applied_.begin(), tally_applied_.end(), 0);
  last_update_ = t;
  next_update_ = t + w_.update_interval;
}

std::vector<double> WindField::save(bool distributed) const {
  std::vector<std::uint64_t> tallies;
  for (const auto* t : {&tally_a_, &tally_b_, &tally_applied_})
    for (std::int64_t q : *t) tallies.push_back(static_cast<std::uint64_t>(q));
  if (distributed) parallel::sum_all(tallies);
  auto tally = [&](std::size_t at) { return static_cast<double>(static_cast<std::int64_t>(tallies[at])); };
  std::vector<double> s = {static_cast<double>(cells_),
                           last_update_,
                           next_update_,
                           snap_.bed_level,
                           snap_.u_star_eff,
                           snap_.drag_per_area,
                           snap_.time,
                           static_cast<double>(snap_.updates)};
  s.insert(s.end(), snap_.u.begin(), snap_.u.end());
  // The tallies stay well below 2^53 by the units' choice, so doubles carry them exactly.
  for (std::size_t k = 0; k < 2 * cells_; ++k) s.push_back(tally(k));
  s.insert(s.end(), snap_.grain_stress.begin(), snap_.grain_stress.end());
  for (std::size_t k = 2 * cells_; k < 3 * cells_; ++k) s.push_back(tally(k));
  s.push_back(snap_.applied_per_area);
  s.insert(s.end(), eddy_.begin(), eddy_.end());  // empty before the first update
  return s;
}

void WindField::restore(const std::vector<double>& s, bool keep_tallies) {
  const std::size_t head = 8, want = head + 5 * cells_ + 1;
  if ((s.size() != want && s.size() != want + cells_ - 1) || static_cast<std::size_t>(s[0]) != cells_)
    throw std::runtime_error(
        fmt::format("checkpoint: the wind state has {} values; this scene's wind needs {}", s.size(), want));
  last_update_ = s[1], next_update_ = s[2], snap_.bed_level = s[3], snap_.u_star_eff = s[4];
  snap_.drag_per_area = s[5], snap_.time = s[6], snap_.updates = static_cast<int>(s[7]);
  auto at = s.begin() + head;
  const long c = static_cast<long>(cells_);
  std::copy(at, at + c, snap_.u.begin());
  auto tally = [&](long from) { return keep_tallies ? static_cast<std::int64_t>(at[from]) : 0; };
  for (std::size_t k = 0; k < cells_; ++k) {
    const long kk = static_cast<long>(k);
    tally_a_[k] = tally(c + kk), tally_b_[k] = tally(2 * c + kk), tally_applied_[k] = tally(4 * c + kk);
  }
  std::copy(at + 3 * c, at + 4 * c, snap_.grain_stress.begin());
  snap_.applied_per_area = at[5 * c];
  eddy_.assign(at + 5 * c + 1, s.end());
  snap_.u_clean =
      fluid::wind_profile({w_.model, w_.kappa, w_.roughness, f_.viscosity, w_.u_star}, heights_above_bed(),
                          std::vector<double>(cells_, w_.u_star * w_.u_star));
}

}  // namespace grainlab::dem
