#include "world3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "parallel.hpp"
#include "stepping.hpp"
#include "world3d_detail.hpp"

namespace grainlab::dem {

using detail3d::effective_gravity;
using detail3d::turned;

namespace {
// The general path's threads: OpenMP's (OMP_NUM_THREADS, else every core), but one a rank when MPI ranks
// share the machine (mpirun -np 2 on two cores would otherwise run four threads on them), unless
// OMP_NUM_THREADS says otherwise. The sums are the same on any number (find_listed_contacts).
int narrow_phase_threads() {
#ifdef _OPENMP
  if (parallel::size() > 1 && !std::getenv("OMP_NUM_THREADS")) return 1;
  return omp_get_max_threads();
#else
  return 1;
#endif
}

// A sphere's (or a cube's) inertia is the same about every axis: turning it changes nothing, so the
// rotation matrices can be skipped (the hot path of sphere beds).
bool isotropic(const Mat3& m) {
  return m(0, 1) == 0 && m(0, 2) == 0 && m(1, 0) == 0 && m(1, 2) == 0 && m(2, 0) == 0 && m(2, 1) == 0 &&
         m(0, 0) == m(1, 1) && m(1, 1) == m(2, 2);
}
}  // namespace

Mat3 Body3::world_inv_inertia() const {
  if (isotropic) return inv_inertia;
  const Mat3 R = q.toRotationMatrix();
  return R * inv_inertia * R.transpose();
}

Vec3 Body3::angular_momentum() const {
  if (isotropic) return inertia * w;
  const Mat3 R = q.toRotationMatrix();
  return R * inertia * R.transpose() * w;
}

World3d::World3d(const Scene& scene, Decomposition decomposition)
    : scene_(scene),
      effects_(scene.effects),
      decomposition_(decomposition),
      threads_(narrow_phase_threads()) {
  if (effects_.has(Effect::wind_drag))
    throw InputError({scene.path, 0}, "effects",
                     "the native engine models \"wind_drag\" in 2-D only so far (docs/saltation.md)");
  if (!scene_.assemblies.empty()) {  // generated beds become bodies (hulls point into scene_)
    scene_.bodies3d = expanded_bodies3d(scene);
    scene_.assemblies.clear();
  }
  n_mat_ = std::max<int>(1, static_cast<int>(scene_.materials.size()));
  laws_ = contact_law_table(scene_);
  for (const Body3Spec& s : scene_.bodies3d) {
    Body3 b;
    b.id = s.id;
    b.x = s.position;
    b.v = s.velocity;
    b.q = s.orientation;
    b.w = effects_.has(Effect::rotation) ? s.spin : Vec3::Zero();
    b.m = s.mass;
    b.inv_m = s.held ? 0 : 1 / s.mass;
    b.inertia = s.inertia;
    b.inv_inertia = effects_.has(Effect::rotation) && !s.held ? Mat3(s.inertia.inverse()) : Mat3::Zero();
    b.held = s.held;
    if (s.held) b.v.setZero(), b.w.setZero();
    b.isotropic = isotropic(b.inertia) && isotropic(b.inv_inertia);
    b.hull = s.shape == Body3Spec::Shape::Polyhedron ? &s.hull : nullptr;
    b.radius = s.radius;
    b.material = s.material;
    b_.push_back(b);
  }
  for (const PlaneSpec& p : scene_.planes) {
    planes_.push_back({p.point, p.normal});
    plane_v_.push_back(Vec3::Zero());
    plane_material_.push_back(p.material);
  }
  place_planes(0);  // moving planes to where they start
  dt_ = scene_.accuracy.dt;
  if (decomposition_.distributed) check_decomposition();
}

// The narrow phase's view of each body, before placement. Only the general path uses it, so a bed on the
// sphere kernel never holds it (a Placed3 is about 400 bytes, as much as the kernel's whole sphere).
std::vector<Placed3> World3d::unplaced(const std::vector<Body3>& bodies) {
  std::vector<Placed3> placed(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i)
    placed[i].hull = bodies[i].hull, placed[i].radius = bodies[i].radius;
  return placed;
}

// Before anything is written: whether this scene can be spread over the ranks as asked.
void World3d::check_decomposition() const {
  const int ranks = parallel::size(), rows = decomposition_.ranks_y;
  if (rows < 1 || ranks % rows != 0)
    throw InputError({"--ranks-y", 0}, std::to_string(rows),
                     fmt::format("{} ranks cannot form a grid with {} rows", ranks, rows));
  if (rows > 1 && scene_.periodic_y)
    throw InputError({"--ranks-y", 0}, std::to_string(rows),
                     "a 3-D scene periodic in y is split into slabs along x only: leave --ranks-y at 1");
  if (std::any_of(b_.begin(), b_.end(), [](const Body3& b) { return b.held; }))
    throw InputError({scene_.path, 0}, "held", "3-D scenes with bodies held in place run on one rank");
  if (scene_.accuracy.integrator != Integrator::VelocityVerlet ||
      std::any_of(b_.begin(), b_.end(), [](const Body3& b) { return b.hull || !b.isotropic; }))
    throw InputError({scene_.path, 0}, "dimension",
                     "3-D scenes run over MPI ranks as beds of spheres under integrator \"verlet\" "
                     "(docs/parallel.md)");
}

const World3d::Spring* World3d::SpringBook::find(const ContactKey3& key) const {
  const auto it = std::lower_bound(entries_.begin(), entries_.end(), key,
                                   [](const Entry& e, const ContactKey3& k) { return e.first < k; });
  return it != entries_.end() && it->first == key ? &it->second : nullptr;
}

void World3d::SpringBook::sort() {
  if (std::adjacent_find(entries_.begin(), entries_.end(), [](const Entry& x, const Entry& y) {
        return !(x.first < y.first);
      }) == entries_.end())
    return;  // strictly increasing already: nothing to do
  std::stable_sort(entries_.begin(), entries_.end(),
                   [](const Entry& x, const Entry& y) { return x.first < y.first; });
  std::size_t kept = 0;
  for (std::size_t k = 0; k < entries_.size(); ++k) {
    if (k + 1 < entries_.size() && entries_[k + 1].first == entries_[k].first) continue;  // a later one
    entries_[kept++] = entries_[k];
  }
  entries_.resize(kept);
}

Vec3 World3d::angular_acceleration(const Body3& b) const {
  if (!effects_.has(Effect::rotation)) return Vec3::Zero();
  const Mat3 R = b.q.toRotationMatrix();
  const Mat3 I = R * b.inertia * R.transpose();
  return R * b.inv_inertia * R.transpose() * (b.tq - b.w.cross(I * b.w));
}

// ---------------------------------------------------------------- forces

void World3d::add_contact(Body3& a, Body3* b, const ContactPoint3& c, const ContactLaw& law,
                          std::int64_t key_b, double h) {
  const Vec3 ra = c.point - a.x, rb = b ? Vec3(c.point - b->x) : Vec3::Zero();
  Vec3 vrel = a.v + a.w.cross(ra);
  if (b) vrel -= b->v + b->w.cross(rb);
  if (!b) vrel -= plane_v_[static_cast<std::size_t>(-1 - key_b)];  // a moving plane's velocity (or zero)
  const double vn = c.normal.dot(vrel);
  const double meff = b ? a.m * b->m / (a.m + b->m) : a.m;
  const double fn = normal_force(law, c.depth, vn, law.normal.coefficient(meff));
  Vec3 F = fn * c.normal;
  if (effects_.has(Effect::friction)) {
    const Vec3 vt = vrel - vn * c.normal;
    const ContactKey3 key{a.id, key_b, c.feature};
    Vec3 xi = Vec3::Zero();
    if (const Spring* held = history_.find(key)) xi = held->xi;
    F += detail3d::shear_force(law, xi, c.normal, vt, h, meff, fn);
    trial_.append(key, {xi, law.k_s});
  }
  a.f += F;
  if (b) b->f -= F;
  if (effects_.has(Effect::rotation)) {
    a.tq += ra.cross(F);
    if (b) b->tq -= rb.cross(F);
  }
  if (after_step_) step_force_[{a.id, key_b}] += fn;  // contact events only
  ++contacts_now_;
}

void World3d::bin_bodies(SphereCells& cells, std::vector<Vec3>& centres, double skin_fraction) const {
  centres.resize(b_.size());
  double r = 0;
  for (std::size_t i = 0; i < b_.size(); ++i) centres[i] = b_[i].x, r = std::max(r, b_[i].radius);
  if (!cells.stale(centres)) return;
  std::vector<std::uint8_t> held;  // (two bodies held in place are never listed as a pair)
  for (std::size_t i = 0; i < b_.size(); ++i)
    if (b_[i].held) held.resize(b_.size(), 0), held[i] = 1;
  cells.build(centres, r, skin_fraction * r, held.empty() ? nullptr : held.data());
}

// A single fast grain (an impactor, an ejectum) moves half the skin in a few steps, and every rebuild
// of the lists used to start every pair of the bed without its hint and crossings again: a 5,000-grain
// bed paid a full separating-axis search on all its touching pairs after each. The pairs that stay in
// the lists keep what they knew; hints only make the answer sooner, so the contacts are the same to the bit.
void World3d::carry_pair_memory() {
  const std::size_t n = b_.size();
  std::vector<SeparatingHint> separating(cells_.entries(), kNoHint);
  std::vector<GaussCrossings> crossings(cells_.entries());
  if (memory_offsets_.size() == n + 1 && separating_.size() == memory_partners_.size())
    for (std::size_t i = 0; i < n; ++i) {
      std::size_t old = memory_offsets_[i];
      const std::size_t old_end = memory_offsets_[i + 1];
      for (std::size_t e = cells_.first(i); e < cells_.first(i + 1) && old < old_end; ++e) {
        const SphereCells::Index j = *(cells_.begin(0) + e);
        while (old < old_end && memory_partners_[old] < j) ++old;  // (both lists ascend)
        if (old < old_end && memory_partners_[old] == j) {
          separating[e] = separating_[old];
          crossings[e] = std::move(crossings_[old]);
        }
      }
    }
  separating_.swap(separating);
  crossings_.swap(crossings);
  memory_offsets_.assign(cells_.offsets(), cells_.offsets() + n + 1);
  memory_partners_.assign(cells_.begin(0), cells_.begin(0) + cells_.entries());
  separating_build_ = cells_.builds();
}

void World3d::place_bodies(bool first_placement) {
  const auto n = static_cast<std::ptrdiff_t>(b_.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (threaded())
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (b_[i].held && !first_placement) continue;  // (where it was placed first, for good)
    placed_[i].x = b_[i].x;
    placed_[i].q = b_[i].q;
    placed_[i].place();
  }
}

// Each thread takes one contiguous run of bodies, the same from step to step, so the pairs' kept axes and
// crossings stay in its core's cache (handing out blocks as threads came free moved them between cores
// and gained nothing on two). The runs are cut for equal work: a touching pair costs about what twenty
// listed pairs do, and the bodies' touching pairs of the last evaluation say where they are.
void World3d::find_listed_contacts() {
  const std::size_t n = b_.size();
  const int parts = threaded() ? threads_ : 1;
  cut_parts(parts);
  part_contacts_.resize(static_cast<std::size_t>(parts));
  entry_contacts_.resize(cells_.entries());    // (every entry is written below,
  plane_contacts_.resize(n * planes_.size());  // and every plane of a body that is not held)
#pragma omp parallel for schedule(static, 1) num_threads(parts) if (parts > 1)
  for (int p = 0; p < parts; ++p) {
    std::vector<ContactPoint3>& out = part_contacts_[static_cast<std::size_t>(p)];
    out.clear();
    for (std::size_t i = part_start_[p]; i < part_start_[p + 1]; ++i) {
      for (std::size_t e = cells_.first(i); e < cells_.first(i + 1); ++e) {
        const std::size_t j = cells_.begin(0)[e], before = out.size();
        if ((b_[i].x - b_[j].x).norm() < b_[i].radius + b_[j].radius)
          body_body(placed_[i], placed_[j], out, &separating_[e], &crossings_[e]);
        // (two convex bodies touch at a face's clipped points at most: far fewer than 65,536)
        entry_contacts_[e] = static_cast<std::uint16_t>(out.size() - before);
      }
      for (std::size_t k = 0; k < planes_.size() && !b_[i].held; ++k) {
        const std::size_t before = out.size();
        body_plane(placed_[i], planes_[k], out);
        plane_contacts_[i * planes_.size() + k] = static_cast<std::uint16_t>(out.size() - before);
      }
    }
  }
}

void World3d::cut_parts(int parts) {
  const std::size_t n = b_.size();
  touching_.resize(n, 0);
  part_start_.assign(static_cast<std::size_t>(parts) + 1, n);
  part_start_[0] = 0;
  if (parts == 1) return;
  auto work = [&](std::size_t i) {
    return double(cells_.first(i + 1) - cells_.first(i)) + 20.0 * touching_[i];
  };
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) total += work(i);
  double sum = 0;
  int p = 1;
  for (std::size_t i = 0; i < n && p < parts; ++i) {
    sum += work(i);
    if (sum >= total * p / parts) part_start_[static_cast<std::size_t>(p++)] = i + 1;
  }
}

void World3d::place_planes(double t) {
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    const Motion3& m = scene_.planes[k].motion;
    if (!m.active()) continue;
    planes_[k].point = scene_.planes[k].point + m.shift(t);
    plane_v_[k] = m.velocity(t);
  }
}

void World3d::compute_forces(double t, double h) {
  ++diag_.force_evaluations;
  place_planes(t);
  const Vec3 g = effective_gravity(scene_);
  for (Body3& b : b_) {
    b.f = b.m * g;
    b.tq.setZero();
  }
  trial_.clear();
  step_force_.clear();
  contacts_now_ = 0;
  if (!effects_.has(Effect::normal_contact)) return;
  const bool first_placement = placed_.size() != b_.size();
  if (first_placement) placed_ = unplaced(b_);
  place_bodies(first_placement);
  const bool cells = b_.size() >= kCellsFrom;
  if (cells) {
    bin_bodies(cells_, centres_, 0.2);
    if (separating_build_ != cells_.builds() || separating_.size() != cells_.entries()) carry_pair_memory();
    find_listed_contacts();
  }
  std::size_t found = 0, part = 0;  // where body i's pairs' contacts start in its part's buffer
  for (std::size_t i = 0; i < b_.size(); ++i) {
    auto touch = [&](std::size_t j, const ContactPoint3* c, std::size_t count) {
      const ContactLaw& law = laws_[b_[i].material * n_mat_ + b_[j].material];
      for (std::size_t k = 0; k < count; ++k) add_contact(b_[i], &b_[j], c[k], law, b_[j].id, h);
    };
    if (cells) {
      while (i == part_start_[part + 1]) ++part, found = 0;
      const std::vector<ContactPoint3>& from = part_contacts_[part];
      touching_[i] = 0;
      for (std::size_t e = cells_.first(i); e < cells_.first(i + 1); ++e) {
        touch(cells_.begin(0)[e], from.data() + found, entry_contacts_[e]);
        found += entry_contacts_[e], touching_[i] += entry_contacts_[e] > 0;
      }
    } else
      for (std::size_t j = i + 1; j < b_.size(); ++j) {
        if (b_[i].held && b_[j].held) continue;  // (as the lists: held pairs left out)
        if ((b_[i].x - b_[j].x).norm() >= b_[i].radius + b_[j].radius) continue;
        scratch_.clear();
        body_body(placed_[i], placed_[j], scratch_);
        touch(j, scratch_.data(), scratch_.size());
      }
    for (std::size_t k = 0; k < planes_.size() && !b_[i].held; ++k) {
      const ContactPoint3* c = nullptr;
      std::size_t count = 0;
      if (cells) {
        c = part_contacts_[part].data() + found, count = plane_contacts_[i * planes_.size() + k];
        found += count;
      } else {
        scratch_.clear();
        body_plane(placed_[i], planes_[k], scratch_);
        c = scratch_.data(), count = scratch_.size();
      }
      const ContactLaw& law = laws_[b_[i].material * n_mat_ + plane_material_[k]];
      for (std::size_t m = 0; m < count; ++m)
        add_contact(b_[i], nullptr, c[m], law, -1 - static_cast<std::int64_t>(k), h);
    }
  }
}

// ---------------------------------------------------------------- integration

void World3d::decide_mode() {
  if (mode_ != Mode::undecided) return;
  mode_ = sphere_kernel_eligible() ? Mode::spheres : Mode::general;
  if (mode_ == Mode::general && decomposition_.distributed)
    throw InputError({scene_.path, 0}, "dimension",
                     "3-D scenes run over MPI ranks as beds of spheres under integrator \"verlet\" without "
                     "contact events (docs/parallel.md)");
  if (mode_ == Mode::general && (scene_.periodic_x || scene_.periodic_y))
    throw InputError(
        {scene_.path, 0}, scene_.periodic_x ? "periodic_x" : "periodic_y",
        "periodic 3-D boxes run on the sphere kernel: at least 32 spheres, integrator \"verlet\", "
        "and no contact events");
}

void World3d::advance_to(double t_end) {
  decide_mode();
  if (mode_ == Mode::spheres && !bed_loaded_) load_bed();
  advance_steps(t_, dt_, t_end, scene_.accuracy.integrator == Integrator::VelocityVerlet, diag_,
                [this] { step(); });
  if (mode_ == Mode::spheres) store_bed();
}

void World3d::step() {
  const double before = t_;
  if (mode_ == Mode::spheres) {
    const std::uint64_t before_evaluations = bed_.force_evaluations();
    bed_.step(diag_.force_evaluations == 0, t_);
    t_ += dt_;
    diag_.force_evaluations += bed_.force_evaluations() - before_evaluations;
    diag_.region_recuts = bed_.region_recuts();
    contacts_now_ = bed_.contacts();
  } else if (scene_.accuracy.integrator == Integrator::VelocityVerlet)
    step_verlet();
  else
    step_predictor_corrector();
  const double taken = t_ - before;
  count_step(diag_, taken);
  last_contacts_ = contacts_now_;
  if (!after_step_) return;
  // Trapezoid rule over the step: the force at its start is the one that ended the previous step.
  trapezoid_impulses(end_force_, step_force_, taken, impulses_);  // (end_force_: the last step's end)
  end_force_ = step_force_;
  after_step_(t_, taken);
}

// Velocity Verlet for translation; for rotation the world angular momentum is kicked by the torque and
// the orientation advanced by the midpoint rule (second order; torque-free, L is conserved exactly).
void World3d::step_verlet() {
  const double dt = dt_, h = dt / 2;
  if (diag_.force_evaluations == 0) {
    compute_forces(t_, 0);
    commit_history();
  }
  const auto n = static_cast<std::ptrdiff_t>(b_.size());
  const bool threads = threaded();
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Body3& b = b_[static_cast<std::size_t>(i)];
    b.v = half_kicked(b.v, b.f, b.inv_m, h);
    b.x = drifted(b.x, b.v, dt);
    if (!effects_.has(Effect::rotation)) continue;
    const Vec3 L = b.angular_momentum() + h * b.tq;
    b.w = b.world_inv_inertia() * L;
    if (b.isotropic) {  // the half-step orientation cannot change the inertia: skip it
      b.q = turned(b.q, b.w, dt);
      continue;
    }
    Body3 mid = b;
    mid.q = turned(b.q, b.w, h);
    b.q = turned(b.q, mid.world_inv_inertia() * L, dt);
    b.w = b.world_inv_inertia() * L;
  }
  t_ += dt;
  compute_forces(t_, dt);
  commit_history();
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    Body3& b = b_[static_cast<std::size_t>(i)];
    b.v = half_kicked(b.v, b.f, b.inv_m, h);
    if (effects_.has(Effect::rotation)) b.w = b.world_inv_inertia() * (b.angular_momentum() + h * b.tq);
  }
}

// The thesis's predictor-corrector (eq. 2.4), as in 2-D (world.cpp), with the orientation turned by
// the step's mean angular velocity and the gyroscopic term in the angular acceleration.
void World3d::step_predictor_corrector() {
  const Accuracy& acc = scene_.accuracy;
  const std::size_t n = b_.size();
  compute_forces(t_, 0);
  start_ = b_;
  a0_.resize(n), al0_.resize(n);
  double vmax = 0;
  for (std::size_t i = 0; i < n; ++i) {
    a0_[i] = b_[i].f * b_[i].inv_m;
    al0_[i] = angular_acceleration(b_[i]);
    vmax = std::max(vmax, b_[i].v.norm());
  }
  if (v_prev_.size() != n)
    v_prev_.assign(n, Vec3::Zero()), w_prev_.assign(n, Vec3::Zero()), have_prev_ = false;
  const double floor = std::max(acc.velocity_floor, 0.01 * vmax);
  const bool relative_to_change = acc.error_measure == ErrorMeasure::Change;
  for (;;) {
    const double dt = dt_, back = have_prev_ ? dt_prev_ + dt : dt;
    for (std::size_t i = 0; i < n; ++i) {
      Body3& b = b_[i];
      const Body3& s = start_[i];
      b.v = predicted(have_prev_ ? v_prev_[i] : s.v, a0_[i], back);
      b.x = trapezoid(s.x, s.v, b.v, dt);
      if (effects_.has(Effect::rotation)) {
        b.w = predicted(have_prev_ ? w_prev_[i] : s.w, al0_[i], back);
        b.q = turned(s.q, (s.w + b.w) / 2, dt);
      }
    }
    compute_forces(t_ + dt, dt);
    double err = 0;
    auto correct = [&](const Vec3& v0, const Vec3& a0, const Vec3& a1, Vec3& v, double fl) {
      const Vec3 vc = corrected(v0, a0, a1, dt);
      for (int k = 0; k < 3; ++k) err = std::max(err, step_error(vc[k], v[k], v0[k], relative_to_change, fl));
      v = vc;
    };
    for (std::size_t i = 0; i < n; ++i) {
      Body3& b = b_[i];
      const Body3& s = start_[i];
      correct(s.v, a0_[i], b.f * b.inv_m, b.v, floor);
      b.x = trapezoid(s.x, s.v, b.v, dt);
      if (effects_.has(Effect::rotation)) {
        correct(s.w, al0_[i], angular_acceleration(b), b.w, floor / b.radius);
        b.q = turned(s.q, (s.w + b.w) / 2, dt);
      }
    }
    if (!control_step(err, dt, t_, acc, dt_, diag_)) {
      have_prev_ = false;  // as in 2-D: the retry predicts from the step's start alone
      b_ = start_;
      continue;
    }
    for (std::size_t i = 0; i < n; ++i) v_prev_[i] = start_[i].v, w_prev_[i] = start_[i].w;
    dt_prev_ = dt;
    have_prev_ = true;
    t_ += dt;
    commit_history();
    return;
  }
}

// ---------------------------------------------------------------- diagnostics

Energies World3d::energies() const {
  Energies e;
  const Vec3 g = effective_gravity(scene_);
  if (mode_ == Mode::spheres && bed_loaded_) return bed_energies(g);
  for (const Body3& b : b_) {
    e.kinetic_translational += 0.5 * b.m * b.v.squaredNorm();
    if (effects_.has(Effect::rotation)) e.kinetic_rotational += 0.5 * b.w.dot(b.angular_momentum());
    e.potential_gravity -= b.m * g.dot(b.x);
  }
  if (!effects_.has(Effect::normal_contact)) return e;
  std::vector<Placed3> placed = placed_.size() == b_.size() ? placed_ : unplaced(b_);
  for (std::size_t i = 0; i < b_.size(); ++i) {
    placed[i].x = b_[i].x;
    placed[i].q = b_[i].q;
    placed[i].place();
  }
  std::vector<ContactPoint3> cs;
  auto spring = [&](int mat_a, int mat_b) {
    const ContactLaw& law = laws_[mat_a * n_mat_ + mat_b];
    for (const ContactPoint3& c : cs) e.elastic += 0.5 * law.k_n * c.depth * c.depth;
    cs.clear();
  };
  SphereCells near;
  std::vector<Vec3> centres;
  const bool cells = b_.size() >= kCellsFrom;
  if (cells) bin_bodies(near, centres, 0);
  for (std::size_t i = 0; i < b_.size(); ++i) {
    auto pair = [&](std::size_t j) {
      body_body(placed[i], placed[j], cs);
      spring(b_[i].material, b_[j].material);
    };
    if (cells)
      for (const SphereCells::Index* j = near.begin(i); j != near.end(i); ++j) pair(*j);
    else
      for (std::size_t j = i + 1; j < b_.size(); ++j)
        if (!(b_[i].held && b_[j].held)) pair(j);  // (as the force loop: held pairs never counted)
    for (std::size_t k = 0; k < planes_.size(); ++k) {
      body_plane(placed[i], planes_[k], cs);
      spring(b_[i].material, plane_material_[k]);
    }
  }
  if (effects_.has(Effect::friction))
    for (const auto& [key, s] : history_) e.elastic += 0.5 * s.k_s * s.xi.squaredNorm();
  return e;
}

}  // namespace grainlab::dem
