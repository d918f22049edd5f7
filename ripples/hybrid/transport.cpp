#include "transport.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>

#ifdef __SSE2__
#include <immintrin.h>
#endif

#include "parallel.hpp"

namespace grainlab::ripples::hybrid {

void check_transport_options(const TransportOptions& o) {
  for (double v : {o.diameter, o.grain_density, o.fluid_density, o.viscosity, o.g, o.u_star, o.length,
                   o.width, o.height, o.dt_max, o.wind_interval, o.wind_memory})
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("every size, density, speed and time of the hybrid model must be positive");
  if (o.triggers < 1) throw std::invalid_argument("triggers must be at least 1");
  if (!(o.travel > 0) || !(o.travel <= 4)) throw std::invalid_argument("travel must be in (0, 4] diameters");
  if (o.fast_substeps && !o.swept)
    throw std::invalid_argument("fast_substeps needs swept = true: fast grains are found along their paths");
  if (!o.swept && o.travel > 0.5)
    throw std::invalid_argument(
        "a travel above 0.5 d lets grains pass through each other unseen: it needs swept = true");
  if (!(o.loosened_floor > 0) || !(o.loosened_floor <= 1))
    throw std::invalid_argument("loosened_floor must be in (0, 1]");
  if (o.sizes.size() != o.fractions.size() || o.sizes.size() > 8)
    throw std::invalid_argument("grain sizes: one fraction per size, at most 8 sizes");
  double sum = 0;
  for (std::size_t k = 0; k < o.sizes.size(); ++k) {
    if (!(o.sizes[k] > 0) || !(o.fractions[k] > 0) || !std::isfinite(o.sizes[k]))
      throw std::invalid_argument("grain sizes and their fractions must be positive");
    sum += o.fractions[k];
  }
  if (!o.sizes.empty() && std::abs(sum - 1) > kFractionTolerance)
    throw std::invalid_argument("the grain sizes' fractions must sum to 1");
  if (o.ejecta_size != "struck" && o.ejecta_size != "local")
    throw std::invalid_argument("ejecta_size must be \"struck\" or \"local\"");
  if (!o.sizes.empty() && o.recorded)
    throw std::invalid_argument("a recorded splash holds impacts of one grain size: use a Lammel splash");
  if (o.recorded)
    o.recorded->check();
  else
    LammelParameters::named(o.splash);  // throws for an unknown set
}

namespace {
WindColumnParams wind_params(const TransportOptions& o) {
  check_transport_options(o);
  return {o.u_star, o.viscosity, o.fluid_density, o.diameter, o.height * o.diameter};
}
double largest_size(const TransportOptions& o) {
  return o.sizes.empty() ? 1.0 : *std::max_element(o.sizes.begin(), o.sizes.end());
}
// The grid of a run's options: columns as wide as the largest grain, and with swept pairs also the most
// two grains may close on each other in a step (TransportOptions::travel); its x columns grouped into
// blocks (fewer where the domain is short).
CollisionGrid collision_grid(const TransportOptions& o) {
  const double widest = largest_size(o), travel = o.swept ? o.travel : 0;
  CollisionGrid grid(o.length * o.diameter, o.width * o.diameter, o.diameter * widest,
                     o.diameter * (widest + 4.0 / 3.0 * travel), o.diameter * (widest + 2.0 / 3.0 * travel));
  grid.set_blocks(kCollisionBlocks);
  return grid;
}
}  // namespace

long max_ranks(const TransportOptions& o) {
  return collision_grid(o).blocks();
}

Transport::Transport(const TransportOptions& o, HeightField* bed)
    : o_(o),
      bed_(bed),
      splash_(LammelParameters::named(o.recorded ? "paper2021" : o.splash)),
      wind_(wind_params(o)),
      rng_(o.seed),
      grid_(collision_grid(o)),
      law_{o.collision_restitution, o.collision_friction} {
  d_ = o.diameter, s_ = o.grain_density / o.fluid_density, g_hat_ = (1 - 1 / s_) * o.g;
  t_unit_ = std::sqrt(d_ / g_hat_), length_ = o.length * d_, width_ = o.width * d_, area_ = length_ * width_;
  mixed_ = !o.sizes.empty(), local_ejecta_ = mixed_ && o.ejecta_size == "local";
  r_max_ = 0.5 * largest_size(o) * d_;
  if (bed && o.wind_follows_bed && o.wind_relief_fades) {
    relief_.emplace(*bed, d_);
    relief_bed_ = bed->heights(), relief_mean_ = bed->mean();
    relief_->refresh(relief_bed_, relief_mean_);
  }
  // A class of grains `size` reference diameters across. The huo2021 drag written out for the hot loop:
  // the acceleration is c (u - v) with c = 3/4 (rho_f / (rho_p d)) C_d |v| and C_d |v| = (sqrt(|v| / 2) +
  // sqrt(24 nu / d))^2 (fluid::drag_rate, tested equal).
  auto size_class = [&](double size) {
    const double d = size * d_, volume = M_PI / 6 * d * d * d, m = o.grain_density * volume;
    return SizeClass{d,
                     m,
                     volume,
                     0.75 * o.fluid_density / (o.grain_density * d),
                     std::sqrt(24 * o.viscosity / d),
                     m * o.g * d,
                     2 * g_hat_ * d * o.dead_rise};
  };
  // The reference grain, which the loops of a bed of one size use directly.
  const SizeClass reference = size_class(1.0);
  m_ = reference.m, volume_ = reference.volume, drag_a_ = reference.drag_a, drag_b_ = reference.drag_b;
  rise2_ = reference.rise2;
  if (!mixed_) classes_.push_back(reference);
  for (double size : o.sizes) classes_.push_back(size_class(size));
  for (const SizeClass& a : classes_)
    for (const SizeClass& b : classes_) coefficients_.push_back(lammel_coefficients(splash_, a.d, b.d));
  if (mixed_) {
    std::vector<double> diameters, masses;
    for (const SizeClass& c : classes_) diameters.push_back(c.d), masses.push_back(c.m);
    grid_.set_sizes(diameters, masses);
  }
  grid_.set_collide_within_splash(o.collide_within_splash);
  for (auto* v : {&drag_mean_, &volume_mean_}) v->assign(wind_.bins(), 0.0);
  for (auto* v : {&drag_now_, &volume_now_}) v->assign(wind_.bins(), 0);
  // Fixed-point units: 2^-16 of the drag gravity would give the reference grain over the longest step,
  // and of its volume over that step, so a wind interval's sums stay exact in a double (checkpoints).
  const double dt_cap = o.dt_max * std::sqrt(d_ / o.g);
  drag_scale_ = 0x1p16 / (m_ * o.g * dt_cap), volume_scale_ = 0x1p16 / (volume_ * dt_cap);
  flux_scale_ = 0x1p32 / (m_ * std::sqrt(o.g * d_));
  if (o.distributed) rank_ = parallel::rank(), ranks_ = parallel::size();
  if (ranks_ > grid_.blocks())
    throw std::invalid_argument(fmt::format("a domain {} d long splits over at most {} MPI ranks, not {}",
                                            o.length, grid_.blocks(), ranks_));
  // Rank r holds blocks [r B / P, (r + 1) B / P).
  for (long x = 0; x < grid_.columns_x(); ++x) {
    int r = 0;
    while (r + 1 < ranks_ && (r + 1) * grid_.blocks() / ranks_ <= grid_.block_of(x)) ++r;
    owner_.push_back(r);
  }
  // Swept steps: a grid of three columns across holds every pair in neighbouring columns, whatever the
  // step.
  if (o.swept && grid_.columns_x() > 3) reach_x_ = grid_.cell_x() - 2 * r_max_;
  if (o.swept && grid_.columns_y() > 3) reach_y_ = grid_.cell_y() - 2 * r_max_;
  // fast_substeps: at dt_max the columns hold the pairs of grains whose velocities lie in a box reach /
  // dt_max wide (less what drag and gravity may change in a step), placed to hold the bulk of a
  // saltation layer: from -0.3 to 0.7 of its width downwind (grains fly downwind), centred across.
  if (o.fast_substeps) {
    const double margin = 2 * std::sqrt(o.g * d_);
    if (reach_x_ < 1e300)
      box_[0] = -0.3 * (reach_x_ / dt_cap - margin), box_[1] = 0.7 * (reach_x_ / dt_cap - margin);
    if (reach_y_ < 1e300)
      box_[2] = -0.5 * (reach_y_ / dt_cap - margin), box_[3] = 0.5 * (reach_y_ / dt_cap - margin);
  }
  first_x_ = std::find(owner_.begin(), owner_.end(), rank_) - owner_.begin();
  last_x_ = std::find(owner_.rbegin(), owner_.rend(), rank_).base() - owner_.begin() - 1;
  const double lift = 20 * std::sqrt(o.g * d_);
  for (int k = 0; k < o.triggers; ++k) {
    const double x = rng_.uniform(0, length_), y = rng_.uniform(0, width_);
    const int kind = mixed_ ? bed_kind(x, y) : 0;
    if (mine(x))  // x, y inside the box
      grains_.add(x, y, (bed_ ? bed_->height(x, y) : 0) + d_, 0, 0, lift, kind, next_id_);
    ++next_id_;
  }
  airborne_ = next_id_;
  v2_launch_ = lift * lift;
  spread_by(0, 0);
  next_wind_ = o.wind_interval * t_unit_;
}

// Sum of m v_x in fixed point, so that it is the same on any rank count.
double Transport::mass_flux() const {
  std::int64_t q = 0;
  for (std::size_t i = 0; i < grains_.size(); ++i)
    q += static_cast<std::int64_t>(classes_[grains_.kind[i]].m * grains_.vx[i] * flux_scale_);
  return static_cast<double>(summed({q})[0]) / flux_scale_ / area_;
}

std::uint64_t Transport::total_collisions() const {
  return static_cast<std::uint64_t>(summed({static_cast<std::int64_t>(collisions)})[0]);
}

std::vector<std::int64_t> Transport::summed(const std::vector<std::int64_t>& v) const {
  if (ranks_ == 1) return v;
  std::vector<std::uint64_t> u(v.begin(), v.end());  // two's complement: the wrapped sum is exact
  parallel::sum_all(u);
  return {u.begin(), u.end()};
}

int Transport::bed_kind(double x, double y) {
  if (!mixed_) return 0;
  if (bed_ && bed_->layer()) return bed_->surface_kind(x, y, rng_.uniform());
  double u = rng_.uniform();  // a fixed bed of the initial mix
  for (std::size_t k = 0; k + 1 < o_.fractions.size(); ++k)
    if ((u -= o_.fractions[k]) < 0) return static_cast<int>(k);
  return static_cast<int>(o_.fractions.size() - 1);
}
double Transport::flux_unit() const {
  return o_.grain_density * d_ * std::sqrt(s_ * g_hat_ * d_);
}
double Transport::shields() const {
  return o_.fluid_density * o_.u_star * o_.u_star / (o_.grain_density * g_hat_ * d_);
}
double Transport::galileo() const {
  return std::sqrt(s_ * g_hat_ * d_ * d_ * d_) / o_.viscosity;
}

double Transport::tau_threshold() const {
  // u*_t^2 = A_N (sigma_p g d + gamma / (rho_f d)), A_N = 0.0123, gamma = 3e-4 N/m = 0.3 g/s^2.
  return 0.0123 * (s_ * o_.g * d_ + 0.3 / (o_.fluid_density * d_));
}

void Transport::step() {
  // The step: no grain moves more than `travel` d (the fastest of the last step's grains and of any
  // launched since, by the splash's bound) and no more than dt_max sqrt(d / g).
  const double v2max = std::max(v2_next_, v2_launch_);
  v2_next_ = 0, v2_launch_ = 0;
  const double dt =
      std::min(o_.dt_max * std::sqrt(d_ / o_.g), v2max > 0 ? o_.travel * d_ / std::sqrt(v2max) : 1e300);
  dt_ = o_.fast_substeps ? o_.dt_max * std::sqrt(d_ / o_.g) : o_.swept ? swept_step(dt) : dt;
  spread_ = {1e300, -1e300, 1e300, -1e300};
  grid_.set_sweep(o_.swept ? dt_ : 0);
  move_grains(dt_);
  grain_steps += airborne_, ++steps;
  if (ranks_ > 1) migrate();
  if (o_.collisions) collide();
  impacts();
  t_ += dt_, since_wind_ += dt_;
  finish_step();
  if (t_ >= next_wind_) update_wind();
}

// A swept step no longer than lets two grains close on each other by the collision columns' margins,
// from the spread of the velocities it starts with, widened by what drag and gravity can change in a
// step (under 0.1 sqrt(g d) each at dt_max: 2 sqrt(g d) in all is ample).
double Transport::swept_step(double dt) const {
  const double margin = 2 * std::sqrt(o_.g * d_);
  if (spread_[1] >= spread_[0]) dt = std::min(dt, reach_x_ / (spread_[1] - spread_[0] + margin));
  if (spread_[3] >= spread_[2]) dt = std::min(dt, reach_y_ / (spread_[3] - spread_[2] + margin));
  return dt;
}

// The grains in flight on all ranks: every rank did every splash, so each knows how many were launched
// and how many settled.
void Transport::finish_step() {
  airborne_ = airborne_ + launched_ - settled_;
  launched_ = 0, settled_ = 0;
}

namespace {
// The grains in ascending id.
Grains by_id(const Grains& g) {
  std::vector<std::size_t> order(g.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto earlier = [&](std::size_t a, std::size_t b) { return g.id[a] < g.id[b]; };
  // Each rank packs its grains in id order, so what was gathered is a run per rank: merged as they come,
  // unless there are many runs (ids are distinct, so either way gives the one order).
  constexpr int kMostRuns = 16;
  std::size_t merged = 0;  // order[0, merged) is in id order
  int runs = 0;
  for (std::size_t i = 1; i <= g.size() && runs <= kMostRuns; ++i)
    if (i == g.size() || g.id[i] < g.id[i - 1]) {
      std::inplace_merge(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(merged),
                         order.begin() + static_cast<std::ptrdiff_t>(i), earlier);
      merged = i, ++runs;
    }
  if (merged < g.size()) std::sort(order.begin(), order.end(), earlier);
  Grains out;
  for (std::size_t i : order)
    out.add(g.x[i], g.y[i], g.z[i], g.vx[i], g.vy[i], g.vz[i], g.kind[i], g.id[i], g.splash[i]);
  return out;
}
}  // namespace

// Grains that flew out of this rank's columns go to the rank that holds them now.
void Transport::migrate() {
  std::vector<std::vector<double>> send(static_cast<std::size_t>(ranks_));
  std::vector<char> gone(grains_.size(), 0);
  for (std::size_t i = 0; i < grains_.size(); ++i) {
    const int r = owner_[static_cast<std::size_t>(grid_.column_x(grains_.x[i]))];
    if (r != rank_) pack_grain(grains_, i, send[static_cast<std::size_t>(r)]), gone[i] = 1;
  }
  const std::vector<std::vector<double>> recv = parallel::all_to_all(send);
  grains_.remove_marked(gone);
  Grains arrived;
  for (const auto& m : recv) unpack_grains(m.data(), m.size() / kGrainValues, arrived);
  grains_.merge(by_id(arrived));
}

void Transport::move_grains(double dt) {
  const bool follows = o_.wind_follows_bed && bed_;
  if (mixed_)
    follows ? move_grains_as<true, true>(dt) : move_grains_as<false, true>(dt);
  else
    follows ? move_grains_as<true, false>(dt) : move_grains_as<false, false>(dt);
}

namespace {
// One grain, or several in the lanes of one vector register: two in SSE2's, four in AVX's. A grain's step
// is a chain of square roots (its speed through the air, then that speed's root in the drag law, at both
// Heun stages) that leaves one grain mostly waiting; the lanes wait once for all. Each lane takes the same
// IEEE operations as one grain alone (no fused multiply-adds), so the results are the same to the last
// bit whatever the width. (Four lanes in two SSE2 registers measured slower: the longer loop body spills.)
#ifdef __AVX__
constexpr int kLanes = 4;
#else
constexpr int kLanes = 2;
#endif
template <int N>
struct Vector;  // N doubles in one register
template <>
struct Vector<2> {
  using type = double __attribute__((vector_size(16)));
};
template <>
struct Vector<4> {
  using type = double __attribute__((vector_size(32)));
};
#ifdef __SSE2__
inline Vector<2>::type root(Vector<2>::type v) {
  return _mm_sqrt_pd(v);
}
#endif
#ifdef __AVX__
inline Vector<4>::type root(Vector<4>::type v) {
  return _mm256_sqrt_pd(v);
}
#endif
template <class V>
V root(V v) {  // without SSE2: lane by lane
  for (std::size_t k = 0; k < sizeof v / sizeof(double); ++k) v[k] = std::sqrt(v[k]);
  return v;
}
template <int N>
struct Lanes {
  using V = typename Vector<N>::type;
  static constexpr int kCount = N;
  static V all(double a) { return V{} + a; }
  static V load(const std::vector<double>& a, std::size_t i) {
    V v;
    std::memcpy(&v, &a[i], sizeof v);
    return v;
  }
  static void store(std::vector<double>& a, std::size_t i, V v) { std::memcpy(&a[i], &v, sizeof v); }
  static V sqrt(V v) { return root(v); }
  static double lane(V v, int k) { return v[k]; }
  template <class F>
  static V each(F f) {
    V v{};  // (every lane is set below; zeroed so that no compiler sees it read unset)
    for (int k = 0; k < N; ++k) v[k] = f(k);
    return v;
  }
};
template <>
struct Lanes<1> {
  using V = double;
  static constexpr int kCount = 1;
  static V all(double a) { return a; }
  static V load(const std::vector<double>& a, std::size_t i) { return a[i]; }
  static void store(std::vector<double>& a, std::size_t i, V v) { a[i] = v; }
  static V sqrt(V v) { return std::sqrt(v); }
  static double lane(V v, int) { return v; }
  template <class F>
  static V each(F f) {
    return f(0);
  }
};
// Whether the kLanes grains from z on all stand clear of the bed's top, as `z - r_max > top` for each.
bool all_above(const double* z, double r_max, double top) {
  typename Vector<kLanes>::type v;
  std::memcpy(&v, z, sizeof v);
  const auto above = v - r_max > top;
  long all = -1;
  for (int k = 0; k < kLanes; ++k) all &= above[k];
  return all != 0;
}
}  // namespace

// The loop once per wind reading and per bed (one size or several), so the column on the mean level (the
// flux runs) pays nothing for the bed lookup and one size nothing for the classes; grains go a register's
// lanes at a time.
template <bool kFollowsBed, bool kMixed>
void Transport::move_grains_as(double dt) {
  const double base = base_, g_hat = g_hat_;
  const bool swept = o_.swept;
  // Per grain-step of h, in the fixed-point units: the drag is m h / 2 times (f1 + f2) and the volume is
  // the grain's times h, each times its scale.
  Grains& g = grains_;
  // The fastest grain's speed squared, in a local: as a member, every store to the grains' arrays (which
  // may alias it, as far as the compiler knows) would force it back to memory each grain.
  double v2 = v2_next_;
  const WindTable wind = wind_.table();
  auto advance = [&](auto lanes, std::size_t i, double h) {
    using L = decltype(lanes);
    using V = typename L::V;
    const SizeClass* c[kLanes] = {};
    V drag_a = L::all(drag_a_), drag_b = L::all(drag_b_);
    if constexpr (kMixed) {
      for (int k = 0; k < L::kCount; ++k) c[k] = &classes_[g.kind[i + k]];
      drag_a = L::each([&](int k) { return c[k]->drag_a; }),
      drag_b = L::each([&](int k) { return c[k]->drag_b; });
    }
    auto accel = [&](V z, V vx, V vy, V vz, V& ax, V& ay, V& az) {
      const V rx = vx - L::each([&](int k) { return wind.at(L::lane(z, k) - base); });
      const V speed = L::sqrt(rx * rx + vy * vy + vz * vz);
      const V root = L::sqrt(0.5 * speed) + drag_b, cd = drag_a * root * root;
      ax = -cd * rx, ay = -cd * vy, az = -cd * vz - g_hat;
      return -cd * rx;  // the drag the wind gives per unit grain mass, x
    };
    const V x = L::load(g.x, i), y = L::load(g.y, i), z0 = L::load(g.z, i);
    const V vx = L::load(g.vx, i), vy = L::load(g.vy, i), vz = L::load(g.vz, i);
    // The wind column's origin under each grain: the mean bed level, or the bed beneath it. A swept step
    // carries a grain over 1.5 d of bed, whose height changes by a tenth of a diameter or more on a
    // ripple's flank, where the wind near the bed changes fast with height: there the second stage reads
    // the wind over the bed where that stage stands.
    V shift = L::all(0), shift2 = shift;
    if constexpr (kFollowsBed) {
      shift = L::each([&](int k) { return bed_->height(L::lane(x, k), L::lane(y, k)) - base; }),
      shift2 = shift;
      if (swept)
        shift2 = L::each([&](int k) {
          return bed_->height(into(L::lane(x, k) + h * L::lane(vx, k), length_),
                              into(L::lane(y, k) + h * L::lane(vy, k), width_)) -
                 base;
        });
      if (relief_) {
        auto felt = [&](V relief, V px, V py, V z_at) {
          return L::each([&](int k) {
            const double r = L::lane(relief, k);
            return relief_->at(L::lane(px, k), L::lane(py, k), L::lane(z_at, k) - base - r, r);
          });
        };
        // (The second stage's place again, as shift2's lookup took it; only swept steps move it.)
        V x2 = x, y2 = y;
        if (swept)
          x2 = L::each([&](int k) { return into(L::lane(x, k) + h * L::lane(vx, k), length_); }),
          y2 = L::each([&](int k) { return into(L::lane(y, k) + h * L::lane(vy, k), width_); });
        const V s1 = felt(shift, x, y, z0), s2 = felt(shift2, x2, y2, z0 + h * vz);
        shift = s1, shift2 = s2;
      }
    }
    V ax, ay, az, bx, by, bz;
    const V z = z0 - shift;
    const V f1 = accel(z, vx, vy, vz, ax, ay, az);
    const V wx = vx + h * ax, wy = vy + h * ay, wz = vz + h * az;
    const V f2 = accel(z + h * vz - (shift2 - shift), wx, wy, wz, bx, by, bz);  // (- 0: same bits)
    const V nx = x + 0.5 * h * (vx + wx), ny = y + 0.5 * h * (vy + wy), nz = z0 + 0.5 * h * (vz + wz);
    const V ux = vx + 0.5 * h * (ax + bx), uy = vy + 0.5 * h * (ay + by), uz = vz + 0.5 * h * (az + bz);
    const V f = f1 + f2;
    L::store(g.x, i, into(nx, length_)), L::store(g.y, i, into(ny, width_)), L::store(g.z, i, nz);
    L::store(g.vx, i, ux), L::store(g.vy, i, uy), L::store(g.vz, i, uz);
    const V speed2 = ux * ux + uy * uy + uz * uz, height = nz - shift2 - base;
    for (int k = 0; k < L::kCount; ++k) {
      v2 = std::max(v2, L::lane(speed2, k));
      const std::size_t bin = wind.bin(L::lane(height, k));
      if constexpr (kMixed) {
        drag_now_[bin] += static_cast<std::int64_t>(c[k]->m * 0.5 * h * drag_scale_ * L::lane(f, k));
        volume_now_[bin] += static_cast<std::int64_t>(c[k]->volume * h * volume_scale_);
      } else {
        drag_now_[bin] += static_cast<std::int64_t>(m_ * 0.5 * h * drag_scale_ * L::lane(f, k));
        volume_now_[bin] += static_cast<std::int64_t>(volume_ * h * volume_scale_);
      }
    }
  };
  // Grains come in id order, not by place: on a bed larger than the cache's second level a bed lookup may
  // miss it, so the rows under the grains kFetchAhead on are asked for while these move. (A few per cent
  // of the move on the paper's domain, whose step is bound by arithmetic: docs/hybrid.md.)
  constexpr std::size_t kFetchAhead = 16;
  std::size_t fetched = 0;
  if constexpr (kFollowsBed)
    fetched = bed_->heights().size() * sizeof(double) > (std::size_t{1} << 18) ? g.size() : 0;
  // fast_substeps: a grain faster than travel / dt takes n substeps of dt / n, n as few as keep it within
  // travel in each (alone, not in a register's lanes, which take the same operations).
  const bool substeps = o_.fast_substeps;
  const double most = o_.travel * d_ / dt, most2 = most * most;
  auto substeps_of = [&](std::size_t k) {
    const double v2k = g.vx[k] * g.vx[k] + g.vy[k] * g.vy[k] + g.vz[k] * g.vz[k];
    return v2k > most2 ? static_cast<int>(std::ceil(std::sqrt(v2k) / most)) : 1;
  };
  auto alone = [&](std::size_t k) {
    const int n = substeps ? substeps_of(k) : 1;
    for (int step = 0; step < n; ++step) advance(Lanes<1>{}, k, n == 1 ? dt : dt / n);
  };
  std::size_t i = 0;
  for (; i + kLanes <= g.size(); i += kLanes) {
    if constexpr (kFollowsBed)
      for (std::size_t k = i + kFetchAhead; k < i + kFetchAhead + kLanes && k < fetched; ++k)
        bed_->prefetch(g.x[k], g.y[k]);
    bool all_one = true;
    if (substeps)
      for (std::size_t k = i; k < i + kLanes; ++k) all_one = all_one && substeps_of(k) == 1;
    if (all_one) {
      advance(Lanes<kLanes>{}, i, dt);
      continue;
    }
    for (std::size_t k = i; k < i + kLanes; ++k) alone(k);
  }
  for (; i < g.size(); ++i) alone(i);
  v2_next_ = v2;
}

void Transport::collide() {
  collisions += grid_.collide_all(grains_, m_, law_);
  if (ranks_ > 1) collide_rank_edges();
  if (o_.fast_substeps) return collide_fast();  // (which applies the shifts)
  if (o_.swept) grid_.apply_shifts(grains_);
}

namespace {
// Whether two columns are neighbours (periodic), as the column pass pairs them.
bool neighbours(long a, long b, long n) {
  const long d = std::abs(a - b);
  return std::min(d, n - d) <= 1;
}
}  // namespace

// The pairs the columns cannot hold at a step of dt_max: those with a grain whose velocity lies outside
// the box. Every rank gathers every such fast grain, and every grain of its own in the columns where one
// of them may have met it within the step; all ranks then collide the same pairs in the same order
// (ascending id of the fast grain, then of its partner), so the bits do not depend on the split. Pairs
// in neighbouring columns were done by the column pass and are left out. The columns are where the
// grains stood in that pass, before its shifts.
void Transport::collide_fast() {
  const Grains& g = grains_;
  std::vector<double> mine;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (fast(g.vx[i], g.vy[i])) pack_grain(g, i, mine);
  const std::vector<double> fast_all = ranks_ > 1 ? parallel::gather_all(mine) : mine;
  if (fast_all.empty()) return grid_.apply_shifts(grains_);
  Grains t;  // the fast grains, then their possible partners
  unpack_grains(fast_all.data(), fast_all.size() / kGrainValues, t);
  t = by_id(t);
  const std::size_t nf = t.size();
  // The columns where a grain with a velocity in the box ends the step if it touched fast grain i within
  // it: the separation now is the one at contact (under 2 r_max) plus the relative velocity times the
  // time since.
  const long nx = grid_.columns_x(), ny = grid_.columns_y();
  const double span = dt_, reach = 2 * r_max_;
  struct Region {  // columns, x0 <= x1 and y0 <= y1: within a period of the grain's own (wrap takes them in)
    long x0, x1, y0, y1;
  };
  auto range = [&](double p, double v, double lo, double hi, double cell, long n, long& a, long& b) {
    const double from = p + std::min(0.0, (lo - v) * span) - reach;
    const double to = p + std::max(0.0, (hi - v) * span) + reach;
    // (On a domain of three columns or fewer across, the box is unbounded that way, every column a
    // neighbour: the span is then compared in columns before any cast to long could overflow.)
    if ((to - from) / cell + 1 >= static_cast<double>(n)) {
      a = 0, b = n - 1;
      return;
    }
    a = static_cast<long>(std::floor(from / cell)), b = static_cast<long>(std::floor(to / cell));
    if (b - a + 1 >= n) a = 0, b = n - 1;
  };
  std::vector<Region> regions(nf);
  marked_.resize(static_cast<std::size_t>(nx * ny), 0);
  std::vector<std::size_t> set;  // the marked columns, to clear them after
  // (Less the fast grain's own column and its neighbours, whose pairs the column pass did.)
  auto beyond = [&](std::size_t i, long cx, long cy) {
    return !neighbours(wrap(cx, nx), grid_.column_x(t.x[i]), nx) ||
           !neighbours(wrap(cy, ny), grid_.column_y(t.y[i]), ny);
  };
  for (std::size_t i = 0; i < nf; ++i) {
    Region& r = regions[i];
    range(t.x[i], t.vx[i], box_[0], box_[1], grid_.cell_x(), nx, r.x0, r.x1);
    range(t.y[i], t.vy[i], box_[2], box_[3], grid_.cell_y(), ny, r.y0, r.y1);
    for (long cx = r.x0; cx <= r.x1; ++cx)
      for (long cy = r.y0; cy <= r.y1; ++cy) {
        const auto c = static_cast<std::size_t>(wrap(cx, nx) * ny + wrap(cy, ny));
        if (!marked_[c] && beyond(i, cx, cy)) marked_[c] = 1, set.push_back(c);
      }
  }
  // This rank's grains in those columns (as the column pass found them), then every rank's.
  mine.clear();
  for (std::size_t i = 0; i < g.size(); ++i)
    if (marked_[grid_.column_of(i)] && !fast(g.vx[i], g.vy[i])) pack_grain(g, i, mine);
  for (std::size_t c : set) marked_[c] = 0;
  const std::vector<double> near_all = ranks_ > 1 ? parallel::gather_all(mine) : mine;
  {
    Grains near;
    unpack_grains(near_all.data(), near_all.size() / kGrainValues, near);
    near = by_id(near);
    for (std::size_t k = 0; k < near.size(); ++k)
      t.add(near.x[k], near.y[k], near.z[k], near.vx[k], near.vy[k], near.vz[k], near.kind[k], near.id[k],
            near.splash[k]);
  }
  std::vector<std::size_t> column(t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    column[k] = static_cast<std::size_t>(grid_.column_x(t.x[k]) * ny + grid_.column_y(t.y[k]));
  auto near = [&](std::size_t a, std::size_t b) {  // neighbouring columns: the column pass paired them
    return neighbours(static_cast<long>(column[a] / static_cast<std::size_t>(ny)),
                      static_cast<long>(column[b] / static_cast<std::size_t>(ny)), nx) &&
           neighbours(static_cast<long>(column[a] % static_cast<std::size_t>(ny)),
                      static_cast<long>(column[b] % static_cast<std::size_t>(ny)), ny);
  };
  std::vector<std::vector<std::uint32_t>> partners(nf);
  // Fast with fast: only pairs whose separation now is within what contact plus the span's relative
  // motion allows, found by a sweep along x (the grains sorted by x, each against those ahead within the
  // widest such window).
  {
    double fastest = 0;
    for (std::size_t i = 0; i < nf; ++i) fastest = std::max(fastest, std::hypot(t.vx[i], t.vy[i]));
    const double window = reach + 2 * fastest * span;
    std::vector<std::uint32_t> order(nf);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return t.x[a] < t.x[b]; });
    for (std::size_t n = 0; n < nf; ++n)
      for (std::size_t m = 1; m < nf; ++m) {  // ahead along x, around the period
        const std::uint32_t i = order[n], j = order[(n + m) % nf];
        const double ahead = t.x[j] - t.x[i] + (n + m >= nf ? length_ : 0.0);
        if (ahead > window) break;
        const double dx = nearest(t.x[j] - t.x[i], length_);
        const double wx = t.vx[j] - t.vx[i], wy = t.vy[j] - t.vy[i], wz = t.vz[j] - t.vz[i];
        if (std::abs(dx) > reach + std::abs(wx) * span ||
            std::abs(nearest(t.y[j] - t.y[i], width_)) > reach + std::abs(wy) * span ||
            std::abs(t.z[j] - t.z[i]) > reach + std::abs(wz) * span || near(i, j))
          continue;
        partners[std::min(i, j)].push_back(std::max(i, j));  // (fast grains: index order is id order)
      }
  }
  // Fast with the others, by column: each column's grains chained from its head (the heads are left clear;
  // the order within a column does not matter, as each list is put in id order below).
  constexpr std::uint32_t kNoGrain = ~std::uint32_t{0};
  near_head_.resize(static_cast<std::size_t>(nx * ny), kNoGrain);
  std::vector<std::uint32_t> near_next(t.size(), kNoGrain);
  for (auto k = static_cast<std::uint32_t>(nf); k < t.size(); ++k)
    near_next[k] = near_head_[column[k]], near_head_[column[k]] = k;
  for (std::uint32_t i = 0; i < nf; ++i) {
    const Region& r = regions[i];
    for (long cx = r.x0; cx <= r.x1; ++cx)
      for (long cy = r.y0; cy <= r.y1; ++cy) {
        const auto c = static_cast<std::size_t>(wrap(cx, nx) * ny + wrap(cy, ny));
        for (std::uint32_t j = near_head_[c]; j != kNoGrain; j = near_next[j])
          if (!near(i, j)) partners[i].push_back(j);
      }
  }
  for (std::size_t k = nf; k < t.size(); ++k) near_head_[column[k]] = kNoGrain;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (std::uint32_t i = 0; i < nf; ++i) {
    auto& p = partners[i];  // in ascending id
    std::sort(p.begin(), p.end(), [&](std::uint32_t a, std::uint32_t b) { return t.id[a] < t.id[b]; });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    for (std::uint32_t j : p) pairs.emplace_back(i, j);
  }
  std::vector<double> shifts;
  std::vector<std::uint32_t> touched;
  const std::uint64_t hits = grid_.collide_pairs(t, pairs, m_, law_, shifts, touched);
  fast_collisions += hits;
  if (rank_ == 0) collisions += hits;
  grid_.apply_shifts(grains_);  // the column pass's
  // The outcome for this rank's own grains among those collided here.
  for (const std::uint32_t k : touched) {
    const auto at = std::lower_bound(grains_.id.begin(), grains_.id.end(), t.id[k]);
    if (at == grains_.id.end() || *at != t.id[k]) continue;
    const auto i = static_cast<std::size_t>(at - grains_.id.begin());
    grains_.vx[i] = t.vx[k], grains_.vy[i] = t.vy[k], grains_.vz[i] = t.vz[k];
    grains_.x[i] = into(grains_.x[i] + shifts[3 * k], length_);
    grains_.y[i] = into(grains_.y[i] + shifts[3 * k + 1], width_);
    grains_.z[i] += shifts[3 * k + 2];
  }
}

// The block boundaries between this rank and its neighbours: each side sends the grains of its edge
// column (as they are after the pairs within blocks), and both sides collide the pairs across, so each
// has its own grains' results. The boundary's left side counts them.
void Transport::collide_rank_edges() {
  const std::size_t n = grains_.size();
  std::vector<std::uint32_t> first, last;
  for (std::uint32_t i = 0; i < n; ++i) {
    const long x = grid_.column_x(grains_.x[i]);
    if (x == first_x_) first.push_back(i);
    if (x == last_x_) last.push_back(i);
  }
  std::vector<double> message{static_cast<double>(first.size())};
  for (auto i : first) pack_grain(grains_, i, message);
  message.push_back(static_cast<double>(last.size()));
  for (auto i : last) pack_grain(grains_, i, message);
  const int left = (rank_ + ranks_ - 1) % ranks_, right = (rank_ + 1) % ranks_;
  std::vector<std::vector<double>> send(static_cast<std::size_t>(ranks_));
  send[static_cast<std::size_t>(left)] = message, send[static_cast<std::size_t>(right)] = message;
  const std::vector<std::vector<double>> recv = parallel::all_to_all(send);
  // The left neighbour's last column, then the right neighbour's first, appended as ghosts.
  auto ghosts = [&](int from, bool its_last) {
    const double* v = recv[static_cast<std::size_t>(from)].data();
    std::size_t count = static_cast<std::size_t>(v[0]);
    if (its_last) v += 1 + count * kGrainValues, count = static_cast<std::size_t>(v[0]);
    std::vector<std::uint32_t> at;
    for (std::size_t k = 0; k < count; ++k) at.push_back(static_cast<std::uint32_t>(grains_.size() + k));
    unpack_grains(v + 1, count, grains_);
    return at;
  };
  const std::vector<std::uint32_t> left_ghosts = ghosts(left, true), right_ghosts = ghosts(right, false);
  collisions += grid_.collide_across(grains_, last, right_ghosts, m_, law_, true);
  grid_.collide_across(grains_, left_ghosts, first, m_, law_, false);
  grains_.truncate(n);
}

// Every new grain is numbered on every rank (they all do every splash), and kept by the rank it is over.
void Transport::launch(double x, double y, double bed_height, double vx, double vy, double vz, int kind) {
  const std::uint64_t id = next_id_++;
  ++launched_;
  spread_by(vx, vy);
  if (mine(x))
    grains_.add(x, y, bed_height + 0.5 * classes_[static_cast<std::size_t>(kind)].d, vx, vy, vz, kind, id,
                splash_now_);
  tally.bed_px -= vx, tally.bed_pz += vz;
  v2_launch_ = std::max(v2_launch_, vx * vx + vy * vy + vz * vz);
}

void Transport::rebound(const Hit& h, double x, double y, double z, double vx, double vy, double vz) {
  spread_by(vx, vy);  // (on every rank: each does every splash)
  if (h.local < 0) return;
  const auto i = static_cast<std::size_t>(h.local);
  grains_.splash[i] = splash_now_;
  grains_.x[i] = x, grains_.y[i] = y, grains_.z[i] = z;
  grains_.vx[i] = vx, grains_.vy[i] = vy, grains_.vz[i] = vz;
}

// Where a grain that ends the step with its bottom (radius r) below the bed crossed the bed's surface.
void Transport::crossing(const Hit& h, double r, double& x, double& y) const {
  const double back = time_since_crossing(
      {h.x, h.y, h.z}, {h.vx, h.vy, h.vz}, r, dt_,
      [&](double px, double py) { return bed_ ? bed_->height(into(px, length_), into(py, width_)) : 0.0; });
  x = into(h.x - h.vx * back, length_), y = into(h.y - h.vy * back, width_);
}

// (remove_marked reads only the flags it has: grains past them, launched in this step, stay.)
void Transport::settle(const Hit& h) {
  ++tally.deaths, ++settled_;
  if (h.local < 0) return;
  const auto i = static_cast<std::size_t>(h.local);
  if (dead_.size() <= i) dead_.resize(i + 1, 0);
  dead_[i] = 1;
}

// The grains at or below the bed beneath them, as the bed stands before this step's splashes: this
// rank's, or (distributed) every rank's, in ascending id, which is the order the splashes are done in.
std::vector<Transport::Hit> Transport::hits() {
  const double top = bed_ ? bed_->top() : 0, r_max = r_max_;
  const double slack = 1e-9 * d_;  // more than rounding can lift height() above the key points around it
  const Grains& g = grains_;
  std::vector<Hit> out;
  const bool swept = o_.swept;
  if (swept)  // every grain as collided: the next step starts from these
    for (std::size_t i = 0; i < g.size(); ++i) spread_by(g.vx[i], g.vy[i]);
  for (std::size_t i = 0; i < g.size(); ++i) {
    // Most grains, at the cost of one test, a register's lanes at a time where they fill one.
    if (i % kLanes == 0 && i + kLanes <= g.size() && all_above(&g.z[i], r_max, top)) {
      i += kLanes - 1;
      continue;
    }
    if (g.z[i] - r_max > top) continue;
    const double bottom = g.z[i] - 0.5 * classes_[g.kind[i]].d;
    if (bottom > top) continue;
    // Above its tile's highest key point, by more than the interpolation's rounding could raise the
    // surface: above the bed beneath it too, as the exact test would find.
    if (bed_ && (bottom > bed_->tile_top(g.x[i], g.y[i]) + slack || bottom > bed_->height(g.x[i], g.y[i])))
      continue;
    out.push_back(
        {g.id[i], g.x[i], g.y[i], g.z[i], g.vx[i], g.vy[i], g.vz[i], g.kind[i], static_cast<long>(i)});
  }
  if (ranks_ == 1) return out;
  // Each rank's message: its fastest grain and its grains' spread of velocities (the next step's size),
  // how many hits, then each hit.
  std::vector<double> mine{v2_next_,   spread_[0], spread_[1],
                           spread_[2], spread_[3], static_cast<double>(out.size())};
  for (const Hit& h : out) {
    mine.insert(mine.end(), {static_cast<double>(h.id), h.x, h.y, h.z, h.vx, h.vy, h.vz,
                             static_cast<double>(h.kind), static_cast<double>(h.local)});
  }
  const std::vector<double> all = parallel::gather_all(mine);
  out.clear();
  for (std::size_t k = 0, r = 0; k < all.size(); ++r) {
    v2_next_ = std::max(v2_next_, all[k]);
    spread_by(all[k + 1], all[k + 3]), spread_by(all[k + 2], all[k + 4]);
    const auto count = static_cast<std::size_t>(all[k + 5]);
    k += 6;
    for (std::size_t n = 0; n < count; ++n, k += 9) {
      const double* v = &all[k];
      const long local = static_cast<int>(r) == rank_ ? static_cast<long>(v[8]) : -1;
      out.push_back({static_cast<std::uint64_t>(v[0]), v[1], v[2], v[3], v[4], v[5], v[6],
                     static_cast<int>(v[7]), local});
    }
  }
  std::sort(out.begin(), out.end(), [](const Hit& a, const Hit& b) { return a.id < b.id; });
  return out;
}

// Every rank does every splash, in the same order with the same generator, so the bed, the tally and the
// generator stay the same everywhere; each rank applies the outcome to its own grains and keeps the
// launched grains over its columns.
void Transport::impacts() {
  std::vector<Hit> list = hits();
  dead_.clear();  // sized at the first grain that settles: most steps have none
  for (Hit& h : list) splash(h);
  if (!dead_.empty()) grains_.remove_marked(dead_);
}

// A grain whose bottom is below the bed beneath it while moving into the bed rebounds (or settles, if it
// cannot rise a diameter) and ejects bed grains, all in the frame of the bed triangle beneath it.
void Transport::splash(Hit& h) {
  const int k1 = h.kind;
  const SizeClass& c1 = classes_[static_cast<std::size_t>(k1)];
  const double r = 0.5 * c1.d, bottom = h.z - r;
  if (bed_ && bottom > bed_->height(h.x, h.y)) return;  // the splashes before this one lowered the bed
  // Where it met the bed: where it is, or (swept steps, long enough to carry a grain a diameter or two
  // into the bed) where its path crossed the surface.
  double px = h.x, py = h.y;
  if (o_.swept) crossing(h, r, px, py);
  const BedPoint facet = bed_ ? bed_->at(px, py) : BedPoint{0, 0, 0, 1};
  if (h.vx * facet.nx + h.vy * facet.ny + h.vz * facet.nz >= 0) {  // leaving the bed; buried only if
    if (bed_ && bottom < facet.h - c1.d) bed_->deposit(h.x, h.y, k1), settle(h);  // the bed rose over it
    return;
  }
  // The splash's frame: the triangle hit (the paper's), or the level bed for a grain coming down.
  const bool level = o_.splash_level && h.vz < 0;
  const BedPoint b = level ? BedPoint{facet.h, 0, 0, 1} : facet;
  const double vn = h.vx * b.nx + h.vy * b.ny + h.vz * b.nz;
  double tx = h.vx - vn * b.nx, ty = h.vy - vn * b.ny, tz = h.vz - vn * b.nz;
  const double vt = std::sqrt(tx * tx + ty * ty + tz * tz), speed = std::hypot(vt, vn);
  if (vt > 0) {
    tx /= vt, ty /= vt, tz /= vt;
  } else {  // straight down: any tangent, taken downwind
    const double k = 1 / std::hypot(b.nz, b.nx);
    tx = b.nz * k, ty = 0, tz = -b.nx * k;
  }
  const double theta = std::atan2(-vn, vt);
  tally.impacts += 1, tally.speed_sum += speed, tally.angle_sum += theta;
  if (impact_log) impact_log->push_back({t_, px, py, h.vx, h.vy, h.vz, facet.nx, facet.ny, facet.nz, k1});
  // The splash's number: one of the grains' numbers, unused by any grain (ids only need to ascend).
  splash_now_ = next_id_++;
  tally.bed_px += h.vx, tally.bed_pz -= h.vz;
  if (o_.recorded) {
    recorded_splash(h, px, py, b, {tx, ty, tz}, speed, theta);
    return;
  }
  // The bed grain it meets (its size is d2 of the splash; the ejecta are of its size).
  const int k2 = bed_kind(px, py);
  const SizeClass& c2 = classes_[static_cast<std::size_t>(k2)];
  const LammelCoefficients& coefficients =
      coefficients_[static_cast<std::size_t>(k1) * classes_.size() + static_cast<std::size_t>(k2)];
  const double e_bar = std::max(0.0, mean_restitution(coefficients, c1.d, c2.d, theta));
  const double up = rebound_angle(coefficients, theta, rng_.uniform()), speed_out = e_bar * speed;
  const double along = speed_out * std::cos(up), off = speed_out * std::sin(up);
  const double ux = along * tx + off * b.nx, uy = along * ty + off * b.ny, uz = along * tz + off * b.nz;
  if (up > 0 && uz > 0 && uz * uz > c1.rise2) {
    rebound(h, px, py, b.h + r, ux, uy, uz);
    v2_launch_ = std::max(v2_launch_, speed_out * speed_out);
    tally.bed_px -= ux, tally.bed_pz += uz;
  } else {  // dead: it settles
    settle(h);
    if (bed_) bed_->deposit(px, py, k1);
  }
  const EjectaLaw ejecta = ejecta_law(splash_, e_bar, 0.5 * c1.m * speed * speed, c2.e_d2 * loosening_);
  const int count = sample_ejecta_count(ejecta, rng_);
  for (int k = 0; k < count; ++k) {
    const double energy = sample_ejectum_energy(ejecta, rng_);
    int kind = k2;
    double rho = 0, phi = 0;
    if (local_ejecta_) {  // each ejectum of the size found where it sits, if the energy lifts it
      rho = c1.d * std::sqrt(rng_.uniform()), phi = 2 * M_PI * rng_.uniform();
      kind = bed_kind(into(px + rho * std::cos(phi), length_), into(py + rho * std::sin(phi), width_));
      if (energy < classes_[static_cast<std::size_t>(kind)].e_d2 * loosening_) continue;
    }
    const SizeClass& c = classes_[static_cast<std::size_t>(kind)];
    const double v = std::sqrt(2 * energy / c.m);
    const double lift_speed = o_.ejecta_vertical ? v : v * b.nz;
    if (lift_speed * lift_speed <= c.rise2) continue;  // cannot rise a diameter: it stays
    if (!local_ejecta_) rho = c1.d * std::sqrt(rng_.uniform()), phi = 2 * M_PI * rng_.uniform();
    const double x = into(px + rho * std::cos(phi), length_), y = into(py + rho * std::sin(phi), width_);
    if (bed_ && !bed_->erode(x, y, kind)) continue;   // the erodible layer is used up here
    const double hb = bed_ ? bed_->height(x, y) : 0;  // the launch direction is the impact's normal
    if (o_.ejecta_vertical)
      launch(x, y, hb, 0, 0, v, kind);
    else
      launch(x, y, hb, v * b.nx, v * b.ny, v * b.nz, kind);
    ++tally.ejecta;
  }
}

// The splash as recorded impacts: one impact of the nearest cell (speed in sqrt(g d), angle in the frame
// of the triangle hit), its rebound scaled by the speed over the cell's, its ejecta launched as recorded
// from where they sat. Frame: t along the incident motion in the bed plane, n the bed's normal, a = n x t.
// The same rules as the Lammel splash: a rebound or ejectum that cannot rise a diameter stays.
void Transport::recorded_splash(Hit& h, double px, double py, const BedPoint& b,
                                const std::array<double, 3>& t, double speed, double theta) {
  const double scale = std::sqrt(o_.g * d_), rise2 = rise2_;
  const std::array<double, 3> n{b.nx, b.ny, b.nz};
  const std::array<double, 3> a{n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                                n[0] * t[1] - n[1] * t[0]};
  auto world = [&](const RecordedVelocity& v, double k, int axis) {
    return k * (v.along * t[axis] + v.normal * n[axis] + v.across * a[axis]);
  };
  const RecordedCell& cell = o_.recorded->nearest(speed / scale, theta * 180 / M_PI);
  const RecordedImpact& hit = cell.draw(rng_.uniform());
  const double k = speed / cell.speed;  // cm/s per sqrt(g d) of the rebound: scaled to this impact's speed
  const double uz = world(hit.rebound, k, 2);
  if (hit.rebounded && uz > 0 && uz * uz > rise2) {
    const double ux = world(hit.rebound, k, 0), uy = world(hit.rebound, k, 1);
    rebound(h, px, py, b.h + 0.5 * d_, ux, uy, uz);
    v2_launch_ = std::max(v2_launch_, ux * ux + uy * uy + uz * uz);
    tally.bed_px -= ux, tally.bed_pz += uz;
  } else {  // dead: it settles
    settle(h);
    if (bed_) bed_->deposit(px, py);
  }
  for (const RecordedEjectum& e : hit.ejecta) {
    const double vz = world(e.launch, scale, 2);
    if (vz * vz <= rise2) continue;  // cannot rise a diameter: it stays
    const double x = into(px + d_ * (e.along * t[0] + e.across * a[0]), length_);
    const double y = into(py + d_ * (e.along * t[1] + e.across * a[1]), width_);
    if (bed_ && !bed_->erode(x, y)) continue;  // the erodible layer is used up here
    launch(x, y, bed_ ? bed_->height(x, y) : 0, world(e.launch, scale, 0), world(e.launch, scale, 1), vz, 0);
    ++tally.ejecta;
  }
}

// The drag's running mean over wind_memory, then the steady column; the bed's mean level is the wind's
// origin, and the wind-loosened surface follows the new stress at the bed.
void Transport::update_wind() {
  const double a = std::min(1.0, since_wind_ / (o_.wind_memory * t_unit_));
  const std::vector<std::int64_t> drag = summed(drag_now_), volume = summed(volume_now_);
  for (std::size_t k = 0; k < wind_.bins(); ++k) {
    drag_mean_[k] += a * (static_cast<double>(drag[k]) / drag_scale_ / since_wind_ - drag_mean_[k]);
    volume_mean_[k] += a * (static_cast<double>(volume[k]) / volume_scale_ / since_wind_ - volume_mean_[k]);
  }
  std::fill(drag_now_.begin(), drag_now_.end(), 0), std::fill(volume_now_.begin(), volume_now_.end(), 0);
  wind_.solve(drag_mean_, volume_mean_, area_);
  if (o_.wind_loosened) loosening_ = std::max(o_.loosened_floor, 1 - wind_.bed_stress() / tau_threshold());
  if (bed_) bed_->refresh(), base_ = bed_->mean();
  // The relief moves with the ripples, a few hundredths of a diameter in ten updates; its transform on a
  // wide bed costs more than the update itself, so it is taken every kReliefEvery updates.
  if (relief_ && ++winds_since_relief_ >= kReliefEvery)
    winds_since_relief_ = 0, relief_bed_ = bed_->heights(), relief_mean_ = base_,
    relief_->refresh(relief_bed_, relief_mean_);
  next_wind_ = t_ + o_.wind_interval * t_unit_, since_wind_ = 0;
}

namespace {
const std::vector<std::string> kGrainColumns = {"x", "y", "z", "vx", "vy", "vz"};
const std::vector<std::string> kWindColumns = {"drag_mean", "volume_mean", "drag_now", "volume_now"};
const std::vector<std::string> kClockColumns = {
    "t",         "next_wind", "since_wind", "v2_next",     "v2_launch", "base",
    "loosening", "rng_high",  "rng_low",    "grain_steps", "steps",     "collisions",
    "impacts",   "speed_sum", "angle_sum",  "deaths",      "ejecta"};
const std::vector<std::string> kSpreadColumns = {"vx_least", "vx_most", "vy_least", "vy_most"};

}  // namespace

const SampleTable& checkpoint_table(const std::map<std::string, SampleTable>& tables, const std::string& name,
                                    std::size_t columns) {
  const auto it = tables.find(name);
  if (it == tables.end()) throw std::invalid_argument("the checkpoint has no table " + name);
  for (const auto& row : it->second.rows)
    if (row.size() != columns) throw std::invalid_argument("table " + name + " has rows of the wrong width");
  return it->second;
}

const SampleTable& checkpoint_table(const std::map<std::string, SampleTable>& tables,
                                    const std::string& name) {
  const auto it = tables.find(name);
  return checkpoint_table(tables, name, it == tables.end() ? 0 : it->second.columns.size());
}

SampleTable grid_table(std::string name, std::string description, const std::vector<double>& values,
                       std::size_t nx) {
  SampleTable t{std::move(name), std::move(description), {}, {}};
  for (std::size_t i = 0; i < nx; ++i) t.columns.push_back(fmt::format("x{}", i));
  for (std::size_t k = 0; k + nx <= values.size(); k += nx)
    t.rows.emplace_back(values.begin() + static_cast<long>(k), values.begin() + static_cast<long>(k + nx));
  return t;
}

std::vector<double> grid_values(const SampleTable& t) {
  std::vector<double> out;
  for (const auto& r : t.rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

std::vector<SampleTable> Transport::save(const std::string& prefix) const {
  // Every rank's grains, in id order.
  std::vector<double> packed;
  for (std::size_t i = 0; i < grains_.size(); ++i) pack_grain(grains_, i, packed);
  if (ranks_ > 1) packed = parallel::gather_all(packed);
  Grains all;
  unpack_grains(packed.data(), packed.size() / kGrainValues, all);
  all = by_id(all);
  SampleTable grains{prefix + "grains", "airborne grains: cm, cm/s", kGrainColumns, {}};
  SampleTable ids{
      prefix + "ids", "airborne grains' numbers, in the order of grains; then the next number", {"id"}, {}};
  SampleTable splashes{prefix + "splashes",
                       "airborne grains' splash numbers (-1: none), in the order of grains",
                       {"splash"},
                       {}};
  for (std::size_t i = 0; i < all.size(); ++i) {
    grains.rows.push_back({all.x[i], all.y[i], all.z[i], all.vx[i], all.vy[i], all.vz[i]});
    ids.rows.push_back({static_cast<double>(all.id[i])});
    splashes.rows.push_back({splash_value(all.splash[i])});
  }
  ids.rows.push_back({static_cast<double>(next_id_)});
  const std::vector<std::int64_t> drag = summed(drag_now_), volume = summed(volume_now_);
  SampleTable wind{prefix + "wind", "the grains' drag and volume per wind bin", kWindColumns, {}};
  for (std::size_t k = 0; k < drag_mean_.size(); ++k)
    wind.rows.push_back({drag_mean_[k], volume_mean_[k], static_cast<double>(drag[k]) / drag_scale_,
                         static_cast<double>(volume[k]) / volume_scale_});
  const std::uint64_t rng = rng_.state();
  SampleTable clock{
      prefix + "clock",
      "time, wind clock, step bounds, bed level, E_eff / E_d2, generator state, counters",
      kClockColumns,
      {{t_, next_wind_, since_wind_, v2_next_, v2_launch_, base_, loosening_, static_cast<double>(rng >> 32),
        static_cast<double>(rng & 0xffffffffull), static_cast<double>(grain_steps),
        static_cast<double>(steps), static_cast<double>(total_collisions()), tally.impacts, tally.speed_sum,
        tally.angle_sum, static_cast<double>(tally.deaths), static_cast<double>(tally.ejecta)}}};
  std::vector<SampleTable> out{grains, ids, splashes, wind, clock};
  if (o_.swept)
    out.push_back({prefix + "spread",
                   "swept steps: the least and most v_x and v_y the next step starts from, cm/s",
                   kSpreadColumns,
                   {{spread_[0], spread_[1], spread_[2], spread_[3]}}});
  if (relief_) {  // (the layers are the relief of the bed as it stood then, not as it stands now)
    out.push_back(grid_table(prefix + "relief_bed", "key-point heights when the relief was last taken (cm)",
                             relief_bed_, bed_->nx()));
    out.push_back({prefix + "relief_clock",
                   "wind updates since the relief was taken, and its bed's mean level (cm)",
                   {"updates", "mean"},
                   {{static_cast<double>(winds_since_relief_), relief_mean_}}});
  }
  if (!mixed_) return out;
  SampleTable kinds{prefix + "kinds", "airborne grains' size classes, in the order of grains", {"kind"}, {}};
  for (auto k : all.kind) kinds.rows.push_back({static_cast<double>(k)});
  out.push_back(kinds);
  return out;
}

void Transport::restore(const std::map<std::string, SampleTable>& tables, const std::string& prefix) {
  const SampleTable& wind = checkpoint_table(tables, prefix + "wind", kWindColumns.size());
  const SampleTable& clock = checkpoint_table(tables, prefix + "clock", kClockColumns.size());
  if (wind.rows.size() != drag_mean_.size() || clock.rows.size() != 1)
    throw std::invalid_argument("the checkpoint's wind or clock does not fit this run");
  grains_ = {};
  const auto& rows = checkpoint_table(tables, prefix + "grains", kGrainColumns.size()).rows;
  const std::vector<std::vector<double>> none;
  const auto& kinds = mixed_ ? checkpoint_table(tables, prefix + "kinds", 1).rows : none;
  if (mixed_ && kinds.size() != rows.size())
    throw std::invalid_argument("the checkpoint's grain sizes do not match its grains");
  // Ids: as saved, or (a checkpoint from before they existed) the rows' order.
  std::vector<std::uint64_t> numbers(rows.size());
  std::iota(numbers.begin(), numbers.end(), std::uint64_t{0});
  next_id_ = rows.size();
  if (tables.count(prefix + "ids")) {
    const auto& ids = checkpoint_table(tables, prefix + "ids", 1).rows;
    if (ids.size() != rows.size() + 1)
      throw std::invalid_argument("the checkpoint's ids do not match its grains");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!(ids[i][0] >= 0 && ids[i][0] < 0x1p53) || (i > 0 && !(ids[i][0] > ids[i - 1][0])))
        throw std::invalid_argument("the checkpoint's grain ids are not ascending whole numbers");
      numbers[i] = static_cast<std::uint64_t>(ids[i][0]);
    }
    if (!(ids.back()[0] >= 0 && ids.back()[0] < 0x1p53) ||
        (!rows.empty() && !(ids.back()[0] > ids[rows.size() - 1][0])))
      throw std::invalid_argument("the checkpoint's next grain id is not above its grains'");
    next_id_ = static_cast<std::uint64_t>(ids.back()[0]);
  }
  // Splash numbers: as saved. A checkpoint from before they existed ran with every pair colliding, and
  // continues the same only so.
  std::vector<std::uint64_t> splash(rows.size(), kNoSplash);
  if (!tables.count(prefix + "splashes") && !o_.collide_within_splash)
    throw std::invalid_argument(
        "the checkpoint is from a build whose grains of one splash collided with each other (before "
        "2026-12-03): continue it with collide_within_splash, or start again");
  if (tables.count(prefix + "splashes")) {
    const auto& s = checkpoint_table(tables, prefix + "splashes", 1).rows;
    if (s.size() != rows.size())
      throw std::invalid_argument("the checkpoint's splash numbers do not match its grains");
    for (std::size_t i = 0; i < rows.size(); ++i) {
      if (!(s[i][0] == -1 ||
            (s[i][0] >= 0 && s[i][0] < static_cast<double>(next_id_) && s[i][0] == std::floor(s[i][0]))))
        throw std::invalid_argument(
            "the checkpoint's splash numbers are not whole numbers below its next id");
      splash[i] = splash_number(s[i][0]);
    }
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const double kind = mixed_ ? kinds[i][0] : 0;
    if (!(kind >= 0 && kind < static_cast<double>(classes_.size())))
      throw std::invalid_argument("the checkpoint has a grain of an unknown size class");
    if (!(r[0] >= 0 && r[0] < length_ && r[1] >= 0 && r[1] < width_))
      throw std::invalid_argument("the checkpoint has a grain outside the domain");
    if (mine(r[0]))
      grains_.add(r[0], r[1], r[2], r[3], r[4], r[5], static_cast<int>(kind), numbers[i], splash[i]);
  }
  airborne_ = rows.size();
  // The sums since the last wind update: all on the first rank (fixed point, exact below 2^53 units).
  for (std::size_t k = 0; k < drag_mean_.size(); ++k) {
    const auto& r = wind.rows[k];
    drag_mean_[k] = r[0], volume_mean_[k] = r[1];
    drag_now_[k] = rank_ == 0 ? std::llround(r[2] * drag_scale_) : 0;
    volume_now_[k] = rank_ == 0 ? std::llround(r[3] * volume_scale_) : 0;
  }
  const auto& c = clock.rows[0];
  t_ = c[0], next_wind_ = c[1], since_wind_ = c[2], v2_next_ = c[3], v2_launch_ = c[4], base_ = c[5];
  loosening_ = c[6];
  rng_.set_state((static_cast<std::uint64_t>(c[7]) << 32) | static_cast<std::uint64_t>(c[8]));
  grain_steps = static_cast<std::uint64_t>(c[9]), steps = static_cast<std::uint64_t>(c[10]);
  collisions = rank_ == 0 ? static_cast<std::uint64_t>(c[11]) : 0;
  tally = {c[12], c[13], c[14], static_cast<std::uint64_t>(c[15]), static_cast<std::uint64_t>(c[16])};
  if (o_.swept) {
    const SampleTable& spread = checkpoint_table(tables, prefix + "spread", kSpreadColumns.size());
    if (spread.rows.size() != 1)
      throw std::invalid_argument("the checkpoint's velocity spread is not one row");
    for (std::size_t k = 0; k < 4; ++k) spread_[k] = spread.rows[0][k];
  }
  // The wind as it was: solved from the same running means at the last update.
  wind_.solve(drag_mean_, volume_mean_, area_);
  if (relief_) {
    relief_bed_ = grid_values(checkpoint_table(tables, prefix + "relief_bed", bed_->nx()));
    const SampleTable& clock = checkpoint_table(tables, prefix + "relief_clock", 2);
    if (relief_bed_.size() != bed_->heights().size() || clock.rows.size() != 1)
      throw std::invalid_argument("the checkpoint's relief_bed or relief_clock does not fit this bed");
    winds_since_relief_ = static_cast<int>(clock.rows[0][0]), relief_mean_ = clock.rows[0][1];
    relief_->refresh(relief_bed_, relief_mean_);
  }
}

}  // namespace grainlab::ripples::hybrid
