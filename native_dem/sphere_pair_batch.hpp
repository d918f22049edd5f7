#pragma once
// The sphere kernel's pair forces four contacts at a time. The sweep's scan finds the touching pairs of a
// block of rows and leaves each one's separation here; batch_forces computes their forces, torques and
// springs with one vector instruction per operation across four contacts (AVX: four doubles a register),
// and the rows then add them up in their usual order.
//
// Each lane does the IEEE operations the scalar row does (SphereBed::Kernel::row, contact_law.hpp), in the
// same order, and a branch of the scalar law becomes a choice between both outcomes computed: so every
// force, torque and spring has the scalar code's bits, and so do the sums, added in the same order.
// (No fused multiply-adds: the build leaves FMA off.)
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "contact_law.hpp"
#include "lanes4.hpp"
#include "world_types.hpp"

namespace grainlab::dem {

// The touching pairs of a block of rows, in row order: who (slots i < j of the pair's row and partner,
// the place k of its spring) and the separation d = x_i - x_j the scan measured; batch_forces adds each one's
// force on i, and torques on i and j. Arrays are padded to whole groups of four.
struct PairBatch {
  static constexpr std::size_t kCapacity = 256;
  enum Column { dx, dy, dz, r2, reach, fx, fy, fz, tax, tay, taz, tbx, tby, tbz, kColumns };
  std::size_t n = 0;
  std::vector<double> columns = std::vector<double>(kColumns * (kCapacity + 4));
  std::vector<std::uint32_t> i = std::vector<std::uint32_t>(kCapacity + 4),
                             j = std::vector<std::uint32_t>(kCapacity + 4);
  std::vector<std::size_t> k = std::vector<std::size_t>(kCapacity + 4);

  double* operator[](Column c) { return columns.data() + c * (kCapacity + 4); }
  const double* operator[](Column c) const { return columns.data() + c * (kCapacity + 4); }
  bool fits(std::size_t more) const { return n + more <= kCapacity; }
  void add(std::uint32_t row, std::uint32_t partner, std::size_t spring, double x, double y, double z,
           double rr, double reach_) {
    i[n] = row, j[n] = partner, k[n] = spring;
    (*this)[dx][n] = x, (*this)[dy][n] = y, (*this)[dz][n] = z, (*this)[r2][n] = rr,
    (*this)[reach][n] = reach_;
    ++n;
  }
  // The last group's spare lanes repeat the last pair's inputs (computed, never used).
  void pad() {
    for (std::size_t c = n; c % 4 != 0; ++c) {
      i[c] = i[n - 1], j[c] = j[n - 1], k[c] = k[n - 1];
      for (Column col : {dx, dy, dz, r2, reach}) (*this)[col][c] = (*this)[col][n - 1];
    }
  }
};

// Forces (fx..fz: on i, its opposite on j), torques (ta on i, tb on j, to be subtracted) and the springs
// (written back to springs) of the batch's pairs under one contact law. hs: the springs' increment.
// m and r: the spheres' masses and radii by slot (arrays, or anything indexed as one).
template <bool Friction, bool Rotation, class Masses, class Radii>
void batch_forces(PairBatch& b, const ContactLaw& law, double hs, const Vec3* v, const Vec3* w,
                  const Masses& m, const Radii& r, Vec3* springs) {
  using namespace lanes4;
  if (b.n == 0) return;
  b.pad();
  const V4 two = splat(2), zero = splat(0);
  for (std::size_t c = 0; c < b.n; c += 4) {
    const std::uint32_t *at_i = &b.i[c], *at_j = &b.j[c];
    const T4 d{load(&b[PairBatch::dx][c]), load(&b[PairBatch::dy][c]), load(&b[PairBatch::dz][c])};
    const V4 dist = lanes4::sqrt(load(&b[PairBatch::r2][c])), depth = load(&b[PairBatch::reach][c]) - dist;
    const T4 n{d.x / dist, d.y / dist, d.z / dist};
    // The contact point lies r_i - depth / 2 from i's centre, against the normal (which points j to i).
    const V4 arm = gather(r, at_i) - depth / two;
    const T4 ra{-n.x * arm, -n.y * arm, -n.z * arm}, rb = ra + d;
    T4 vrel;
    if constexpr (Rotation)
      vrel = (gather(v, at_i) + cross(gather(w, at_i), ra)) - (gather(v, at_j) + cross(gather(w, at_j), rb));
    else
      vrel = gather(v, at_i) - gather(v, at_j);
    const V4 vn = dot(n, vrel);
    const V4 mi = gather(m, at_i), mj = gather(m, at_j), meff = mi * mj / (mi + mj);
    V4 c_n = splat(law.normal.coef) + splat(law.normal.rate) * meff;
    if (law.normal.rest != 0) c_n = c_n + splat(law.normal.rest) * lanes4::sqrt(meff);
    V4 fn = splat(law.k_n) * depth - c_n * vn;
    if (law.clip_attractive) fn = pick(fn < zero, zero, fn);  // std::max(fn, 0.0)
    T4 F = fn * n;
    if constexpr (Friction) {
      T4 xi;
      for (int l = 0; l < 4; ++l) {
        const Vec3& s = springs[b.k[c + l]];
        xi.x[l] = s.x(), xi.y[l] = s.y(), xi.z[l] = s.z();
      }
      // lay_into_tangent_plane: laid back into the plane keeping its length, if it has left it.
      const V4 along = dot(n, xi), len2 = dot(xi, xi);
      const T4 laid = xi - along * n;
      const V4 now2 = dot(laid, laid);
      const M4 turned = along != zero, rescaled = turned & (now2 > zero);
      xi = pick(rescaled, lanes4::sqrt(len2 / now2) * laid, pick(turned, laid, xi));
      // shear_force: the spring stretched by the tangential velocity, its force capped at mu max(fn, 0).
      const T4 vt = vrel - vn * n;
      V4 c_s = splat(law.shear.coef) + splat(law.shear.rate) * meff;
      if (law.shear.rest != 0) c_s = c_s + splat(law.shear.rest) * lanes4::sqrt(meff);
      xi = xi + splat(hs) * vt;
      T4 fs = splat(-law.k_s) * xi - c_s * vt;
      const V4 cap = splat(law.mu) * pick(fn < zero, zero, fn);
      const V4 f2 = dot(fs, fs);
      // (Sliding is the exception: the capped force and spring only for a group where some lane slides.)
      if (const M4 capped = f2 > cap * cap; any(capped)) {
        const T4 fs_capped = (cap / lanes4::sqrt(f2)) * fs;
        const V4 ks = splat(law.k_s);
        xi = pick(capped, T4{-fs_capped.x / ks, -fs_capped.y / ks, -fs_capped.z / ks}, xi);
        fs = pick(capped, fs_capped, fs);
      }
      F = F + fs;
      for (int l = 0; l < 4 && c + l < b.n; ++l) springs[b.k[c + l]] = Vec3(xi.x[l], xi.y[l], xi.z[l]);
    }
    store(&b[PairBatch::fx][c], F.x), store(&b[PairBatch::fy][c], F.y), store(&b[PairBatch::fz][c], F.z);
    if constexpr (Rotation) {
      const T4 ta = cross(ra, F), tb = cross(rb, F);
      store(&b[PairBatch::tax][c], ta.x), store(&b[PairBatch::tay][c], ta.y),
          store(&b[PairBatch::taz][c], ta.z);
      store(&b[PairBatch::tbx][c], tb.x), store(&b[PairBatch::tby][c], tb.y),
          store(&b[PairBatch::tbz][c], tb.z);
    }
  }
}

}  // namespace grainlab::dem
