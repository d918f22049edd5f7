#pragma once
// Helpers shared by the 3-D engine's general path (world3d.cpp) and its sphere kernel
// (world3d_spheres.cpp).
#include <algorithm>
#include <cmath>

#include "contact_law.hpp"
#include "lanes4.hpp"
#include "polyhedron.hpp"
#include "scene.hpp"
#include "world_types.hpp"

namespace grainlab::dem::detail3d {

// Orientation after turning at angular velocity w (world frame) for time dt: the turn by the angle |w| dt
// about w, (cos h, w sin(h) / |w|) with h = |w| dt / 2. A step turns a grain by a small angle, and there
// cos h and sin(h) / h are summed as their series in h^2 = w.w dt^2 / 4, which needs neither the square
// root nor sin and cos: in a bed of jostled spheres these were a tenth of the step. The series stop at
// h^8: below h = 0.05 the next terms (h^10 / 10!) lie under the rounding of the sum.
//
// No division is left in the small turn. A poured bed's spheres all spin, and the series' eight
// divisions by constants and the normalisation's square root and divisions were a tenth of its step
// (divisions share one unit with the contacts' square roots). The series multiply by the constants'
// reciprocals instead (a different rounding of terms that are themselves below an ulp of the sum). The
// product of two unit quaternions has a norm within a few ulps of 1, so one Newton step for
// 1 / sqrt(n2) about 1, (3 - n2) / 2, normalises it: its error, 3/8 (n2 - 1)^2, is some 1e-30.
inline Quat unit_after_small_turn(const Quat& q) {
  // |q|^2 as Eigen's squaredNorm sums it (two lanes: (x^2 + z^2) + (y^2 + w^2), under SSE2 or AVX), from
  // the components: Eigen stored the product as two halves and read them back as one 32-byte load, which
  // the processor cannot forward from the stores (a stall of a tenth of a poured bed's sweep).
  const double x = q.x(), y = q.y(), z = q.z(), w = q.w();
  const double n2 = (x * x + z * z) + (y * y + w * w);
  return Quat(q.coeffs() * ((3 - n2) / 2));
}

inline Quat turned(const Quat& q, const Vec3& w, double dt) {
  if (w.x() == 0 && w.y() == 0 && w.z() == 0) return q;  // the identity turn: q stays as it was
  const double h2 = w.squaredNorm() * (dt * dt / 4);
  if (h2 >= 0.05 * 0.05) return (quat_from_rotation_vector(w * dt) * q).normalized();
  // Below h^2 = 1e-16 both sums round to exactly 1 (their first terms are under half an ulp of 1), so
  // they are not summed: the same bits without the series. A resting bed's spheres spin that slowly
  // (h ~ 1e-9), and the turn was then half of what a resting sphere costs per step.
  double cos_h = 1, sinc_h = 1;
  if (h2 >= 1e-16) {
    constexpr double k2 = 1.0 / 2, k12 = 1.0 / 12, k30 = 1.0 / 30, k56 = 1.0 / 56;
    constexpr double k6 = 1.0 / 6, k20 = 1.0 / 20, k42 = 1.0 / 42, k72 = 1.0 / 72;
    cos_h = 1 - h2 * k2 * (1 - h2 * k12 * (1 - h2 * k30 * (1 - h2 * k56)));
    sinc_h = 1 - h2 * k6 * (1 - h2 * k20 * (1 - h2 * k42 * (1 - h2 * k72)));
  }
  const Vec3 axis = w * (sinc_h * dt / 2);
  return unit_after_small_turn(Quat(cos_h, axis.x(), axis.y(), axis.z()) * q);
}

// turned() for four spheres at once, in place: q[l] turned by w[l] over dt, l = 0..3. Each lane does
// turned()'s operations in turned()'s order, with Eigen's quaternion product as its SSE2 code computes it
// (x = (aw bx + ay bz) - (az by - ax bw), ...), so the same bits; a sphere that does not spin keeps its
// q (four of them return at once), and a fast turn (h >= 0.05) goes through turned() itself. A poured bed's
// spheres all spin, and one at a time the turn's chain of dependent multiplications was a quarter of the
// sweep.
inline void turn4(Quat* q, const Vec3* w, double dt) {
  using namespace lanes4;
  const T4 wv{V4{w[0].x(), w[1].x(), w[2].x(), w[3].x()}, V4{w[0].y(), w[1].y(), w[2].y(), w[3].y()},
              V4{w[0].z(), w[1].z(), w[2].z(), w[3].z()}};
  const V4 zero = splat(0), one = splat(1);
  const M4 still = (wv.x == zero) & (wv.y == zero) & (wv.z == zero);
  // Four spheres that do not spin keep their q: a resting lattice's spheres (spins exactly zero by
  // symmetry) then cost no turn at all, as one at a time they did not.
  if (!any(~still)) return;
  const V4 h2 = ((wv.x * wv.x + wv.y * wv.y) + wv.z * wv.z) * splat(dt * dt / 4);
  const M4 fast = h2 >= splat(0.05 * 0.05), tiny = h2 < splat(1e-16);
  constexpr double k2 = 1.0 / 2, k12 = 1.0 / 12, k30 = 1.0 / 30, k56 = 1.0 / 56;
  constexpr double k6 = 1.0 / 6, k20 = 1.0 / 20, k42 = 1.0 / 42, k72 = 1.0 / 72;
  auto series = [&](double a, double b, double c, double d) {
    return one - h2 * splat(a) * (one - h2 * splat(b) * (one - h2 * splat(c) * (one - h2 * splat(d))));
  };
  const V4 aw = pick(tiny, one, series(k2, k12, k30, k56));
  const V4 s = pick(tiny, one, series(k6, k20, k42, k72)) * splat(dt) / splat(2);
  const V4 ax = wv.x * s, ay = wv.y * s, az = wv.z * s;
  const V4 bx{q[0].x(), q[1].x(), q[2].x(), q[3].x()}, by{q[0].y(), q[1].y(), q[2].y(), q[3].y()};
  const V4 bz{q[0].z(), q[1].z(), q[2].z(), q[3].z()}, bw{q[0].w(), q[1].w(), q[2].w(), q[3].w()};
  V4 rx = (aw * bx + ay * bz) - (az * by - ax * bw), ry = (aw * by + ay * bw) + (az * bx - ax * bz);
  V4 rz = (aw * bz - ay * bx) + (az * bw + ax * by), rw = (aw * bw - ay * by) - (az * bz + ax * bx);
  const V4 unit =
      (splat(3) - ((rx * rx + rz * rz) + (ry * ry + rw * rw))) / splat(2);  // unit_after_small_turn
  rx = rx * unit, ry = ry * unit, rz = rz * unit, rw = rw * unit;
  for (int l = 0; l < 4; ++l) {
    if (still[l]) continue;
    q[l] = fast[l] ? turned(q[l], w[l], dt) : Quat(rw[l], rx[l], ry[l], rz[l]);
  }
}

// Gravity as the effects give it: off, as given, or reduced by buoyancy.
inline Vec3 effective_gravity(const Scene& s) {
  if (!s.effects.has(Effect::gravity)) return Vec3::Zero();
  const double keep = s.effects.has(Effect::buoyancy) ? 1 - s.fluid.density / s.fluid.grain_density : 1.0;
  return s.gravity3d * keep;
}

// The shear force of a contact with normal n, tangential velocity vt and normal force fn, from the spring
// xi stored at the last step (zero: a new contact), which is updated in place: laid back into the tangent
// plane, then the law shared with 2-D (contact_law.hpp).
inline Vec3 shear_force(const ContactLaw& law, Vec3& xi, const Vec3& n, const Vec3& vt, double h, double meff,
                        double fn) {
  lay_into_tangent_plane(xi, n);
  return dem::shear_force(law, fn, vt, law.shear.coefficient(meff), h, xi);
}

}  // namespace grainlab::dem::detail3d
