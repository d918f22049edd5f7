#include "world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include "input_error.hpp"
#include "narrow_phase.hpp"
#include "parallel.hpp"
#include "stepping.hpp"

namespace grainlab::dem {

World::World(const Scene& scene, Decomposition decomposition)
    : scene_(scene), effects_(scene.effects), decomposition_(decomposition), g_(scene.gravity) {
  if (scene.periodic_x) {
    xmin_ = scene.periodic_x->first;
    period_ = scene.periodic_x->second - scene.periodic_x->first;
  }
  setup_laws();
  for (const WallSpec& w : scene.walls) {
    Wall wall;
    wall.spec = w;
    wall.at(0);
    walls_.push_back(wall);
  }
  wall_lists_.resize(walls_.size());
  add_bodies_from_scene();
  expand_assemblies();
  if (effects_.has(Effect::buoyancy)) g_ = g_ * (1 - scene.fluid.density / scene.fluid.grain_density);
  if (effects_.has(Effect::wind_drag)) wind_.emplace(scene_, p_, p_.size());
  double rmin = 1e300, rmax = 0;
  for (double r : p_.r) rmin = std::min(rmin, r), rmax = std::max(rmax, r);
  skin_ = scene.accuracy.skin.value_or(p_.size() ? 0.25 * rmin : 1.0);
  check_period(rmax);
  dt_ = scene.accuracy.dt;
  std::fill(p_.vx_prev.begin(), p_.vx_prev.end(), 0.0);
  n_own_ = p_.size();
  if (decomposition_.distributed && parallel::size() > 1) distribute_initial();
  rebuild_neighbors();
}

// A disc meets its neighbours' periodic images once the period holds two interaction ranges (each the
// largest diameter plus the skin); a narrower period would need a disc to meet its own image. Checked
// when the world is made, before any step, so the scene's key is named (exit 2); each list build checks
// again for its own discs (rmax: the largest radius).
void World::check_period(double rmax) const {
  if (period_ <= 0) return;
  const double needed = 2 * (2 * rmax + skin_);
  if (period_ < needed)
    throw InputError(
        {scene_.path, 0}, "scene.periodic_x",
        fmt::format("the period {:g} is shorter than two interaction ranges, {:g} (each the largest "
                    "disc's diameter, {:g}, plus the skin, {:g}): make it wider",
                    period_, needed, 2 * rmax, skin_));
}

void World::setup_laws() {
  n_mat_ = std::max<int>(1, static_cast<int>(scene_.materials.size()));
  laws_ = contact_law_table(scene_);
}

void World::add_particle(const BodySpec& b) {
  const std::size_t i = p_.size();
  p_.resize(i + 1);
  p_.x[i] = b.position.x;
  p_.y[i] = b.position.y;
  p_.th[i] = b.angle;
  p_.vx[i] = b.velocity.x;
  p_.vy[i] = b.velocity.y;
  p_.w[i] = effects_.has(Effect::rotation) ? b.spin : 0.0;
  p_.m[i] = b.mass;
  p_.inv_m[i] = 1 / b.mass;
  p_.inertia[i] = b.inertia;
  p_.inv_inertia[i] = effects_.has(Effect::rotation) ? 1 / b.inertia : 0.0;
  p_.r[i] = b.radius;
  p_.id[i] = b.id;
  p_.mat[i] = b.material;
  if (b.shape == BodySpec::Shape::Polygon) {
    p_.shape[i] = static_cast<std::int32_t>(polygons_.size());
    polygons_.push_back(b.vertices);
  } else {
    p_.shape[i] = -1;
  }
}

void World::add_bodies_from_scene() {
  for (const BodySpec& b : scene_.bodies) add_particle(b);
}

long World::index_of(std::int64_t id) const {
  for (std::size_t i = 0; i < p_.size(); ++i)
    if (p_.id[i] == id) return static_cast<long>(i);
  return -1;
}

// ---------------------------------------------------------------- integration

double World::step() {
  const double t_before = t_;
  if (scene_.accuracy.integrator == Integrator::VelocityVerlet)
    step_verlet();
  else
    step_predictor_corrector();
  count_step(diag_, t_ - t_before);
  if (wind_) {
    const auto w0 = std::chrono::steady_clock::now();
    wind_->after_step(p_, n_own_, t_, t_ - t_before, domain_.has_value());
    diag_.seconds_wind += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  }
  finish_step_impulses(t_ - t_before);
  return t_ - t_before;
}

void World::finish_step_impulses(double taken) {
  if (!after_step_) return;
  trapezoid_impulses(pair_force_start_, pair_force_, taken, impulses_);
  after_step_(t_, taken);
}

void World::advance_to(double t_end) {
  advance_steps(t_, dt_, t_end, scene_.accuracy.integrator == Integrator::VelocityVerlet, diag_,
                [this] { step(); });
}

void World::step_verlet() {
  const std::size_t n = n_own_;
  const double dt = dt_, h = 0.5 * dt;
  if (diag_.force_evaluations == 0) {
    compute_forces(t_, 0.0);
    commit_history();
  }
  if (after_step_) pair_force_start_ = pair_force_;  // the kick below applies these forces
  // One pass: kick, drift, restart the forces from gravity, and track the largest displacement since
  // the neighbour list was built (memory traffic dominates at large N, so passes are fused).
  const double gx = effects_.has(Effect::gravity) ? g_.x : 0.0,
               gy = effects_.has(Effect::gravity) ? g_.y : 0.0;
  double *x = p_.x.data(), *y = p_.y.data(), *vx = p_.vx.data(), *vy = p_.vy.data();
  double *fx = p_.fx.data(), *fy = p_.fy.data();
  const double *im = p_.inv_m.data(), *m = p_.m.data(), *xb = x_build_.data(), *yb = y_build_.data();
  const bool listed = x_build_.size() == n;
  double max_d2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double vxi = half_kicked(vx[i], fx[i], im[i], h), vyi = half_kicked(vy[i], fy[i], im[i], h);
    vx[i] = vxi;
    vy[i] = vyi;
    x[i] = drifted(x[i], vxi, dt);
    y[i] = drifted(y[i], vyi, dt);
    fx[i] = m[i] * gx;
    fy[i] = m[i] * gy;
    if (listed) {
      const double dx = x[i] - xb[i], dy = y[i] - yb[i];
      max_d2 = std::max(max_d2, dx * dx + dy * dy);
    }
  }
  if (effects_.has(Effect::rotation)) {
    double *w = p_.w.data(), *th = p_.th.data(), *tq = p_.tq.data();
    const double* iI = p_.inv_inertia.data();
    for (std::size_t i = 0; i < n; ++i) {
      w[i] = half_kicked(w[i], tq[i], iI[i], h);
      th[i] = drifted(th[i], w[i], dt);
      tq[i] = 0;
    }
  }
  t_ += dt;
  ghosts_fresh_ = false;
  if (any_rank(!listed || max_d2 > 0.25 * skin_ * skin_)) rebuild_neighbors();
  compute_forces(t_, dt, true);  // dashpots see the half-step velocities, as in LAMMPS
  commit_history();
  // A rebuild re-sorts (and reallocates) the particle arrays, and migration changes how many this
  // rank owns: no pointer or count from above survives it.
  for (std::size_t i = 0; i < n_own_; ++i) {
    p_.vx[i] = half_kicked(p_.vx[i], p_.fx[i], p_.inv_m[i], h);
    p_.vy[i] = half_kicked(p_.vy[i], p_.fy[i], p_.inv_m[i], h);
  }
  if (effects_.has(Effect::rotation))
    for (std::size_t i = 0; i < n_own_; ++i) p_.w[i] = half_kicked(p_.w[i], p_.tq[i], p_.inv_inertia[i], h);
}

// The thesis's first-order predictor-corrector (eq. 2.4) with its step control: reject and halve
// when the predicted and corrected velocities differ by more than `tolerance` (relative to the
// velocity, or to its change over the step: Accuracy::error_measure), accept otherwise, and grow by 20 % when
// the difference is small enough that the grown step should still pass (error ~ dt^2, so err * 1.2^2 <=
// tolerance).
void World::step_predictor_corrector() {
  const Accuracy& acc = scene_.accuracy;
  double vmax = 0;
  for (std::size_t i = 0; i < n_own_; ++i) vmax = std::max(vmax, std::hypot(p_.vx[i], p_.vy[i]));
  if (domain_) vmax = parallel::max_all(vmax);
  if (needs_rebuild(2 * vmax * dt_)) rebuild_neighbors();
  const std::size_t n = n_own_;

  compute_forces(t_, 0.0);
  if (after_step_) pair_force_start_ = pair_force_;
  x0_ = p_.x, y0_ = p_.y, th0_ = p_.th, vx0_ = p_.vx, vy0_ = p_.vy, w0_ = p_.w;
  ax0_.resize(n), ay0_.resize(n), al0_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    ax0_[i] = p_.fx[i] * p_.inv_m[i];
    ay0_[i] = p_.fy[i] * p_.inv_m[i];
    al0_[i] = effects_.has(Effect::rotation) ? p_.tq[i] * p_.inv_inertia[i] : 0.0;
  }
  // Ratios are not trusted below a floor: the scene's absolute velocity_floor or 1 % of the fastest
  // particle's speed (a grain at rest, or reversing, next to a moving one must not stall the step).
  const double floor = std::max(acc.velocity_floor, 0.01 * vmax);
  const bool relative_to_change = acc.error_measure == ErrorMeasure::Change;
  for (;;) {
    const double dt = dt_, back = have_prev_ ? dt_prev_ + dt : dt;
    auto predict = [&](const std::vector<double>& vprev, const std::vector<double>& v0,
                       const std::vector<double>& a0, const std::vector<double>& x0, std::vector<double>& v,
                       std::vector<double>& x) {
      for (std::size_t i = 0; i < n; ++i) {
        v[i] = predicted(have_prev_ ? vprev[i] : v0[i], a0[i], back);
        x[i] = trapezoid(x0[i], v0[i], v[i], dt);
      }
    };
    predict(p_.vx_prev, vx0_, ax0_, x0_, p_.vx, p_.x);
    predict(p_.vy_prev, vy0_, ay0_, y0_, p_.vy, p_.y);
    if (effects_.has(Effect::rotation)) predict(p_.w_prev, w0_, al0_, th0_, p_.w, p_.th);
    ghosts_fresh_ = false;
    compute_forces(t_ + dt, dt);

    double err = 0;
    auto correct = [&](const std::vector<double>& v0, const std::vector<double>& a0,
                       const std::vector<double>& f, const std::vector<double>& inv,
                       const std::vector<double>& x0, std::vector<double>& v, std::vector<double>& x,
                       bool spin) {
      for (std::size_t i = 0; i < n; ++i) {
        const double vc = corrected(v0[i], a0[i], f[i] * inv[i], dt);
        err = std::max(err, step_error(vc, v[i], v0[i], relative_to_change, spin ? floor / p_.r[i] : floor));
        v[i] = vc;
        x[i] = trapezoid(x0[i], v0[i], vc, dt);
      }
    };
    correct(vx0_, ax0_, p_.fx, p_.inv_m, x0_, p_.vx, p_.x, false);
    correct(vy0_, ay0_, p_.fy, p_.inv_m, y0_, p_.vy, p_.y, false);
    if (effects_.has(Effect::rotation)) correct(w0_, al0_, p_.tq, p_.inv_inertia, th0_, p_.w, p_.th, true);

    if (domain_) err = parallel::max_all(err);  // every rank accepts or rejects the same step
    if (!control_step(err, dt, t_, acc, dt_, diag_)) {
      // The two-step predictor extrapolates f(t0) back over the whole previous step; when a contact
      // has just begun that error does not shrink with dt0, so the retry predicts from t0 alone.
      have_prev_ = false;
      continue;
    }
    p_.vx_prev.swap(vx0_), p_.vy_prev.swap(vy0_), p_.w_prev.swap(w0_);
    dt_prev_ = dt;
    have_prev_ = true;
    t_ += dt;
    commit_history();
    update_ghosts();  // the corrected state, for energies, contacts and the next step
    return;
  }
}

// ---------------------------------------------------------------- diagnostics

// Each owned particle's share (its kinetic and potential energy, half of each pair spring, all of its
// wall springs) is summed in id order over all ranks: the same bits whatever the decomposition.
Energies World::energies() const {
  const double gx = effects_.has(Effect::gravity) ? g_.x : 0, gy = effects_.has(Effect::gravity) ? g_.y : 0;
  std::vector<double> share(5 * n_own_, 0.0);  // id, translational, rotational, gravity, elastic
  for (std::size_t i = 0; i < n_own_; ++i) {
    double* e = &share[5 * i];
    e[0] = static_cast<double>(p_.id[i]);
    e[1] = 0.5 * p_.m[i] * (p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i]);
    if (effects_.has(Effect::rotation)) e[2] = 0.5 * p_.inertia[i] * p_.w[i] * p_.w[i];
    e[3] = -p_.m[i] * (gx * p_.x[i] + gy * p_.y[i]);
  }
  if (effects_.has(Effect::normal_contact)) {
    // Normal springs and committed shear springs, half to each partner, added in partner-id order.
    std::vector<double> pair_u(discs_.j.size(), 0.0);
    for (std::size_t i = 0; i + 1 < discs_.offset.size(); ++i)
      for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
        const std::uint32_t j = discs_.j[k];
        const double dx = p_.x[i] - p_.x[j] + discs_.shift[k], dy = p_.y[i] - p_.y[j];
        const double depth = p_.r[i] + p_.r[j] - std::sqrt(dx * dx + dy * dy);
        const ContactLaw& L = laws_[p_.mat[i] * n_mat_ + p_.mat[j]];
        if (depth > 0) pair_u[k] += 0.5 * L.k_n * depth * depth;
        if (effects_.has(Effect::friction)) pair_u[k] += 0.5 * L.k_s * discs_.xi[k] * discs_.xi[k];
      }
    for (std::size_t i = 0; i < n_own_; ++i)
      for (std::uint32_t e = discs_.inc_offset[i]; e < discs_.inc_offset[i + 1]; ++e)
        share[5 * i + 4] += 0.5 * pair_u[discs_.inc[e] >> 1];
    for (std::size_t w = 0; w < walls_.size(); ++w)
      for (std::size_t k = 0; k < wall_lists_[w].particle.size(); ++k) {
        const std::uint32_t i = wall_lists_[w].particle[k];
        ContactGeometry c;
        const ContactLaw& L = laws_[p_.mat[i] * n_mat_ + walls_[w].spec.material];
        if (disc_wall_contact({p_.x[i], p_.y[i]}, p_.r[i], walls_[w], c))
          share[5 * i + 4] += 0.5 * L.k_n * c.depth * c.depth;
        if (effects_.has(Effect::friction))
          share[5 * i + 4] += 0.5 * L.k_s * wall_lists_[w].xi[k] * wall_lists_[w].xi[k];
      }
  }
  std::vector<double> all = domain_ ? parallel::gather_all(share) : std::move(share);
  const std::size_t n = all.size() / 5;
  std::vector<std::size_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return all[5 * a] < all[5 * b]; });
  Energies e;
  for (std::size_t k : order) {
    e.kinetic_translational += all[5 * k + 1];
    e.kinetic_rotational += all[5 * k + 2];
    e.potential_gravity += all[5 * k + 3];
    e.elastic += all[5 * k + 4];
  }
  if (effects_.has(Effect::normal_contact)) e.elastic += polygon_elastic_energy();
  return e;
}

// Every contact that involves a polygon (body pairs and vertex-wall contacts), at the current state.
void World::visit_polygon_contacts(
    const std::function<void(const ContactLaw&, const ContactGeometry&, std::uint64_t)>& visit) const {
  std::vector<Vec2> sa, sb;
  auto pose = [&](std::uint32_t i) {
    return BodyPose{
        {p_.x[i], p_.y[i]}, p_.th[i], p_.r[i], p_.shape[i] < 0 ? nullptr : &polygons_[p_.shape[i]]};
  };
  for (const GeneralPair& gp : general_pairs_) {
    BodyPose a = pose(gp.i);
    a.centre.x += gp.shift;
    ContactGeometry c;
    if (body_body_contact(a, pose(gp.j), c, sa, sb))
      visit(laws_[p_.mat[gp.i] * n_mat_ + p_.mat[gp.j]], c, general_key(p_.id[gp.i], p_.id[gp.j], 0));
  }
  for (std::uint32_t i : polygon_particles_)
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      const Wall& wall = walls_[w];
      const BodyPose b = pose(i);
      for (std::size_t v = 0; v < b.vertices->size(); ++v) {
        ContactGeometry c;
        if (vertex_wall_contact(b, v, wall, c))
          visit(laws_[p_.mat[i] * n_mat_ + wall.spec.material], c,
                general_key(p_.id[i], -1 - static_cast<std::int64_t>(w), static_cast<int>(v)));
      }
    }
}

// Spring energy of the polygon contacts: the normal spring, and the committed shear spring of each
// contact, found by its history key (as the disc and wall contacts count theirs).
double World::polygon_elastic_energy() const {
  double u = 0;
  visit_polygon_contacts([&](const ContactLaw& L, const ContactGeometry& c, std::uint64_t key) {
    u += 0.5 * L.k_n * c.depth * c.depth;
    if (!effects_.has(Effect::friction)) return;
    if (const auto it = general_xi_.find(key); it != general_xi_.end())
      u += 0.5 * L.k_s * it->second * it->second;
  });
  return u;
}

std::size_t World::count_contacts() const {
  std::size_t count = 0;
  // A pair with a ghost is on two ranks; the rank owning its row (lower-id) particle counts it.
  for (std::size_t i = 0; i + 1 < discs_.offset.size() && i < n_own_; ++i)
    for (std::uint32_t k = discs_.offset[i]; k < discs_.offset[i + 1]; ++k) {
      const std::uint32_t j = discs_.j[k];
      const double dx = p_.x[i] - p_.x[j] + discs_.shift[k], dy = p_.y[i] - p_.y[j];
      const double rs = p_.r[i] + p_.r[j];
      count += dx * dx + dy * dy < rs * rs;
    }
  for (std::size_t w = 0; w < walls_.size(); ++w)
    for (std::uint32_t i : wall_lists_[w].particle) {
      ContactGeometry c;
      count += disc_wall_contact({p_.x[i], p_.y[i]}, p_.r[i], walls_[w], c);
    }
  visit_polygon_contacts([&](const ContactLaw&, const ContactGeometry&, std::uint64_t) { ++count; });
  if (!domain_) return count;
  std::vector<std::uint64_t> total{count};
  parallel::sum_all(total);
  return total[0];
}

std::size_t World::memory_bytes() const {
  auto bytes = [](const auto& v) {
    return v.capacity() * sizeof(typename std::decay_t<decltype(v)>::value_type);
  };
  std::size_t b = p_.size() * Particles::bytes_per_particle();
  b += bytes(discs_.offset) + bytes(discs_.j) + bytes(discs_.shift) + bytes(discs_.xi) + bytes(discs_.xi_new);
  b += bytes(discs_.force) + bytes(discs_.touching) + bytes(discs_.particle_touching) + bytes(discs_.inc) +
       bytes(discs_.inc_offset);
  b += bytes(x_build_) + bytes(y_build_) + bytes(general_pairs_);
  for (const WallList& L : wall_lists_) b += bytes(L.particle) + bytes(L.xi) + bytes(L.xi_new);
  for (const auto* v : {&x0_, &y0_, &th0_, &vx0_, &vy0_, &w0_, &ax0_, &ay0_, &al0_}) b += bytes(*v);
  return b + (general_xi_.size() + general_xi_new_.size()) * 32;
}

std::size_t World::history_entries() const {
  return discs_.xi.size() + general_xi_.size() + [&] {
    std::size_t s = 0;
    for (const WallList& L : wall_lists_) s += L.xi.size();
    return s;
  }();
}

}  // namespace grainlab::dem
