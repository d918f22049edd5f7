// The 3-D engine's sphere kernel: velocity Verlet on a bed of spheres with the same physics as the
// general path (world3d.cpp: step_verlet, compute_forces, add_contact), written for speed. The hot fields
// live in arrays of their own (a bed's passes touch only what they use), spheres need no placement or
// narrow phase, and each shear spring sits beside its neighbour-list entry (or its body-plane slot)
// instead of in a map keyed by ids: a spring is read and rewritten once per force evaluation, which is
// what committing the general path's trial map amounts to under Verlet. A spring at zero is the same as
// no spring, so a pair out of contact simply holds zero.
#include <algorithm>
#include <cmath>

#include "world3d.hpp"
#include "world3d_detail.hpp"

namespace grainlab::dem {

namespace {
// A spring that holds something (a pair or plane that touched at the last evaluation).
bool holds(const Vec3& xi) {
  return xi.x() != 0 || xi.y() != 0 || xi.z() != 0;
}
// Apart: the spring goes. Reading first, since most entries apart have nothing to clear.
void forget(Vec3& xi) {
  if (holds(xi)) xi.setZero();
}
}  // namespace

bool World3d::sphere_kernel_eligible() const {
  if (!sphere_kernel_allowed_ || after_step_ || b_.size() < kCellsFrom) return false;
  if (scene_.accuracy.integrator != Integrator::VelocityVerlet) return false;
  return std::all_of(b_.begin(), b_.end(), [](const Body3& b) { return !b.hull && b.isotropic; });
}

void World3d::load_spheres() {
  const std::size_t n = b_.size();
  for (auto* v : {&sp_.x, &sp_.v, &sp_.w, &sp_.f, &sp_.tq}) v->resize(n);
  sp_.q.resize(n), sp_.m.resize(n), sp_.inv_m.resize(n), sp_.inv_i.resize(n), sp_.r.resize(n),
      sp_.mat.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Body3& b = b_[i];
    sp_.x[i] = b.x, sp_.v[i] = b.v, sp_.w[i] = b.w, sp_.f[i] = b.f, sp_.tq[i] = b.tq, sp_.q[i] = b.q;
    sp_.m[i] = b.m, sp_.inv_m[i] = b.inv_m, sp_.inv_i[i] = b.inv_inertia(0, 0), sp_.r[i] = b.radius;
    sp_.mat[i] = b.material;
  }
  sp_.plane_xi.resize(n * planes_.size(), Vec3::Zero());
  if (scene_.periodic_x) cells_.set_period(0, scene_.periodic_x->first, scene_.periodic_x->second);
  if (scene_.periodic_y) cells_.set_period(1, scene_.periodic_y->first, scene_.periodic_y->second);
}

void World3d::store_spheres() {
  for (std::size_t i = 0; i < b_.size(); ++i) {
    Body3& b = b_[i];
    b.x = sp_.x[i], b.v = sp_.v[i], b.w = sp_.w[i], b.f = sp_.f[i], b.tq = sp_.tq[i], b.q = sp_.q[i];
  }
}

// Half kick, drift, forces, half kick (as step_verlet; an isotropic body's angular momentum I w + h tq
// turned back into w is w + h tq / I).
void World3d::sphere_step() {
  const double dt = dt_, h = dt / 2;
  const bool rotation = effects_.has(Effect::rotation);
  if (diag_.force_evaluations == 0) sphere_forces(0);
  const std::size_t n = sp_.x.size();
  // Raw pointers, declared unaliased: through the vectors the compiler reloads every array's address
  // after each store.
  Vec3* __restrict x = sp_.x.data(), * __restrict v = sp_.v.data(), * __restrict w = sp_.w.data();
  const Vec3* __restrict f = sp_.f.data(), * __restrict tq = sp_.tq.data();
  const double* __restrict inv_m = sp_.inv_m.data(), * __restrict inv_i = sp_.inv_i.data();
  Quat* __restrict q = sp_.q.data();
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += h * inv_m[i] * f[i];
    x[i] += dt * v[i];
    if (!rotation) continue;
    w[i] += h * inv_i[i] * tq[i];
    if (w[i].x() != 0 || w[i].y() != 0 || w[i].z() != 0) q[i] = detail3d::turned(q[i], w[i], dt);
  }
  t_ += dt;
  sphere_forces(dt);
  for (std::size_t i = 0; i < n; ++i) {
    v[i] += h * inv_m[i] * f[i];
    if (rotation) w[i] += h * inv_i[i] * tq[i];
  }
}

// New neighbour lists when a sphere has moved half the skin; the springs move to their pairs' new
// entries (both lists hold each i's partners j > i in ascending order, so one merge per sphere).
void World3d::rebuild_sphere_lists() {
  if (!cells_.stale(sp_.x)) return;
  // Spheres that crossed a periodic side come back in on the other (only here, so a list's
  // displacements stay continuous between builds).
  for (const auto& [axis, period] :
       {std::make_pair(0, scene_.periodic_x), std::make_pair(1, scene_.periodic_y)})
    if (period)
      for (Vec3& p : sp_.x) {
        const double L = period->second - period->first;
        p[axis] -= L * std::floor((p[axis] - period->first) / L);
      }
  struct Held {
    std::size_t i, j;
    Vec3 xi;
  };
  std::vector<Held> held;
  if (!sp_.pair_xi.empty()) {
    const std::size_t* base = cells_.begin(0);
    for (std::size_t i = 0; i < sp_.x.size(); ++i)
      for (const std::size_t* j = cells_.begin(i); j != cells_.end(i); ++j)
        if (const Vec3& xi = sp_.pair_xi[static_cast<std::size_t>(j - base)]; holds(xi))
          held.push_back({i, *j, xi});
  }
  const double r_max = *std::max_element(sp_.r.begin(), sp_.r.end()), skin = 0.2 * r_max;
  cells_.build(sp_.x, r_max, skin);
  // The planes each sphere can reach before the next rebuild (it moves less than half the skin): most
  // of a bed's spheres touch none of them, and then test none.
  sp_.plane_start.assign(1, 0), sp_.plane_of.clear();
  for (std::size_t i = 0; i < sp_.x.size(); ++i) {
    for (std::size_t k = 0; k < planes_.size(); ++k)
      if (planes_[k].normal.dot(sp_.x[i] - planes_[k].point) < sp_.r[i] + skin) sp_.plane_of.push_back(k);
    sp_.plane_start.push_back(sp_.plane_of.size());
  }
  const std::size_t* base = cells_.begin(0);
  sp_.pair_xi.assign(static_cast<std::size_t>(cells_.end(sp_.x.size() - 1) - base), Vec3::Zero());
  // Both are sorted by (i, j); a held pair missing from the new lists (none is: a pair in contact is
  // within their reach) would just be passed over.
  auto it = held.begin();
  for (std::size_t i = 0; i < sp_.x.size() && it != held.end(); ++i)
    for (const std::size_t* j = cells_.begin(i); j != cells_.end(i); ++j) {
      while (it != held.end() && (it->i < i || (it->i == i && it->j < *j))) ++it;
      if (it != held.end() && it->i == i && it->j == *j)
        sp_.pair_xi[static_cast<std::size_t>(j - base)] = it->xi, ++it;
    }
}

// add_contact for spheres: body i against sphere j, or against a plane (plane = true, j unused).
void World3d::sphere_contact(std::size_t i, std::size_t j, bool plane, const Vec3& n, const Vec3& ra,
                             const Vec3& rb, double depth, const ContactLaw& law, Vec3& xi, double h) {
  Vec3 vrel = sp_.v[i] + sp_.w[i].cross(ra);
  if (!plane) vrel -= sp_.v[j] + sp_.w[j].cross(rb);
  const double vn = n.dot(vrel);
  const double meff = plane ? sp_.m[i] : sp_.m[i] * sp_.m[j] / (sp_.m[i] + sp_.m[j]);
  const double fn = normal_force(law, depth, vn, law.normal.coefficient(meff));
  Vec3 F = fn * n;
  if (effects_.has(Effect::friction)) F += detail3d::shear_force(law, xi, n, vrel - vn * n, h, meff, fn);
  sp_.f[i] += F;
  if (!plane) sp_.f[j] -= F;
  if (effects_.has(Effect::rotation)) {
    sp_.tq[i] += ra.cross(F);
    if (!plane) sp_.tq[j] -= rb.cross(F);
  }
  ++contacts_now_;
}

void World3d::sphere_forces(double h) {
  ++diag_.force_evaluations;
  const Vec3 g = detail3d::effective_gravity(scene_);
  const std::size_t n = sp_.x.size();
  {
    Vec3* __restrict f = sp_.f.data(), * __restrict tq = sp_.tq.data();
    const double* __restrict m = sp_.m.data();
    for (std::size_t i = 0; i < n; ++i) f[i] = m[i] * g, tq[i].setZero();
  }
  contacts_now_ = 0;
  if (!effects_.has(Effect::normal_contact)) return;
  rebuild_sphere_lists();
  const std::size_t* base = cells_.begin(0);
  const Vec3* __restrict x = sp_.x.data();
  const bool periodic = scene_.periodic_x || scene_.periodic_y;
  const double* __restrict r = sp_.r.data();
  Vec3* __restrict pair_xi = sp_.pair_xi.data();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 xi_pos = x[i];
    for (const std::size_t* jp = cells_.begin(i); jp != cells_.end(i); ++jp) {
      const std::size_t j = *jp;
      Vec3& xi = pair_xi[static_cast<std::size_t>(jp - base)];
      const Vec3 d = periodic ? cells_.separation(xi_pos, x[j]) : Vec3(xi_pos - x[j]);  // nearest image
      const double reach = r[i] + r[j], r2 = d.squaredNorm();
      if (r2 >= reach * reach || r2 == 0) {  // apart (as sphere_sphere: depth <= 0 or coincident)
        forget(xi);
        continue;
      }
      const double dist = std::sqrt(r2), depth = reach - dist;
      const Vec3 normal = d / dist;
      // The contact point lies r_i - depth / 2 from i's centre, against the normal (which points j to i).
      const Vec3 ra = -normal * (r[i] - depth / 2), rb = ra + d;
      sphere_contact(i, j, false, normal, ra, rb, depth, laws_[sp_.mat[i] * n_mat_ + sp_.mat[j]], xi, h);
    }
    for (std::size_t c = sp_.plane_start[i]; c < sp_.plane_start[i + 1]; ++c) {
      const std::size_t k = sp_.plane_of[c];
      Vec3& xi = sp_.plane_xi[i * planes_.size() + k];
      const Plane3& p = planes_[k];
      const double depth = sp_.r[i] - p.normal.dot(sp_.x[i] - p.point);
      if (depth <= 0) {
        forget(xi);
        continue;
      }
      sphere_contact(i, i, true, p.normal, -p.normal * (sp_.r[i] - depth / 2), Vec3::Zero(), depth,
                     laws_[sp_.mat[i] * n_mat_ + plane_material_[k]], xi, h);
    }
  }
}

double World3d::sphere_elastic_energy() const {
  double e = 0;
  const std::size_t n = sp_.x.size();
  if (n == 0 || cells_.builds() == 0) return e;  // (no force evaluation yet: no contacts known)
  const bool friction = effects_.has(Effect::friction);
  const std::size_t* base = cells_.begin(0);
  for (std::size_t i = 0; i < n; ++i) {
    for (const std::size_t* j = cells_.begin(i); j != cells_.end(i); ++j) {
      const ContactLaw& law = laws_[sp_.mat[i] * n_mat_ + sp_.mat[*j]];
      const double depth = sp_.r[i] + sp_.r[*j] - cells_.separation(sp_.x[i], sp_.x[*j]).norm();
      if (depth > 0) e += 0.5 * law.k_n * depth * depth;
      if (friction) e += 0.5 * law.k_s * sp_.pair_xi[static_cast<std::size_t>(j - base)].squaredNorm();
    }
    for (std::size_t k = 0; k < planes_.size(); ++k) {
      const ContactLaw& law = laws_[sp_.mat[i] * n_mat_ + plane_material_[k]];
      const double depth = sp_.r[i] - planes_[k].normal.dot(sp_.x[i] - planes_[k].point);
      if (depth > 0) e += 0.5 * law.k_n * depth * depth;
      if (friction) e += 0.5 * law.k_s * sp_.plane_xi[i * planes_.size() + k].squaredNorm();
    }
  }
  return e;
}

}  // namespace grainlab::dem
