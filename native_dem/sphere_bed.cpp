#include "sphere_bed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "sphere_pair_batch.hpp"
#include "stepping.hpp"
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
// Triples for the hot loops: x and y as one SSE2 pair, z alone, loaded and stored as 16 + 8 bytes
// everywhere (Eigen's 3-vectors got spilled as 16 + 8 and reloaded as 8 + 16 in places, which defeats
// store forwarding). Each lane is plain IEEE arithmetic in Eigen's order (its dot and squared norm add
// (a0 b0 + a1 b1) + a2 b2), so the results are the bits scalar code gives.
typedef double Pair __attribute__((vector_size(16)));
struct D3 {
  Pair xy;
  double z;
  D3() = default;
  D3(double x, double y, double z_) : xy{x, y}, z(z_) {}
  D3(Pair p, double z_) : xy(p), z(z_) {}
  double x() const { return xy[0]; }
  double y() const { return xy[1]; }
};
inline D3 get(const Vec3& v) {
  Pair p;
  std::memcpy(&p, v.data(), sizeof p);
  return {p, v.z()};
}
inline void put(Vec3& v, const D3& a) {
  std::memcpy(v.data(), &a.xy, sizeof a.xy);
  v.z() = a.z;
}
inline D3 operator+(const D3& a, const D3& b) {
  return {a.xy + b.xy, a.z + b.z};
}
inline D3 operator-(const D3& a, const D3& b) {
  return {a.xy - b.xy, a.z - b.z};
}
inline D3 operator*(double s, const D3& a) {
  return {s * a.xy, s * a.z};
}
inline D3 operator*(const D3& a, double s) {
  return {a.xy * s, a.z * s};
}
inline D3 operator/(const D3& a, double s) {
  return {a.xy / s, a.z / s};
}
inline D3 operator-(const D3& a) {
  return {-a.xy, -a.z};
}
inline double dot(const D3& a, const D3& b) {
  const Pair p = a.xy * b.xy;
  return (p[0] + p[1]) + a.z * b.z;
}
inline D3 cross(const D3& a, const D3& b) {  // (a.y b.z - a.z b.y, a.z b.x - a.x b.z, a.x b.y - a.y b.x)
  const Pair a1{a.xy[1], a.z}, b1{b.z, b.xy[0]}, a2{a.z, a.xy[0]}, b2{b.xy[1], b.z};
  return {a1 * b1 - a2 * b2, a.xy[0] * b.xy[1] - a.xy[1] * b.xy[0]};
}
inline bool nonzero(const D3& a) {
  return (a.xy[0] != 0) | (a.xy[1] != 0) | (a.z != 0);  // (no short cut: three compares and no branches)
}

// detail3d::shear_force on triples: the same shared law (contact_law.hpp), operation for operation.
inline D3 shear_force_3d(const ContactLaw& law, D3& xi, const D3& n, const D3& vt, double h, double meff,
                         double fn) {
  lay_into_tangent_plane(xi, n);
  return shear_force(law, fn, vt, law.shear.coefficient(meff), h, xi);
}

}  // namespace

bool spring_order(const SphereSpring& p, const SphereSpring& q) {
  if (p.a != q.a) return p.a < q.a;
  if ((p.b < 0) != (q.b < 0)) return p.b >= 0;  // a sphere's pairs, then its planes
  return p.b >= 0 ? p.b < q.b : p.b > q.b;      // planes by index: -1, -2, ...
}

void SphereBed::load(const SphereBedSetup& setup, const std::vector<SphereState>& spheres,
                     double max_radius) {
  s_ = setup;
  max_radius_ = max_radius, skin_ = kSkinPerRadius * max_radius;
  std::vector<std::size_t> order(spheres.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return spheres[a].id < spheres[b].id; });
  const std::size_t n = spheres.size();
  id_.resize(n);
  for (auto* a : {&x_, &v_, &w_, &f_, &tq_}) a->resize(n);
  q_.resize(n), m_.resize(n), inv_m_.resize(n), inv_i_.resize(n), r_.resize(n), mat_.resize(n);
  in_place_.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const SphereState& s = spheres[order[k]];
    id_[k] = s.id, x_[k] = s.x, v_[k] = s.v, w_[k] = s.w, f_[k] = s.f, tq_[k] = s.tq, q_[k] = s.q;
    m_[k] = s.m, inv_m_[k] = 1 / s.m, inv_i_[k] = s.inv_i, r_[k] = s.r, mat_[k] = s.material;
    if (s.held) {
      // Held in place: zero inverse mass and inertia leave every step's kicks and drift exactly where
      // they were, while the contacts still take the mass m into their damping.
      in_place_.resize(n, 0), in_place_[k] = 1;
      inv_m_[k] = 0, inv_i_[k] = 0, v_[k].setZero(), w_[k].setZero();
    }
  }
  one_kind_ = n > 0;
  if (n > 0) kind_ = {m_[0], inv_m_[0], inv_i_[0], r_[0]};
  for (std::size_t k = 1; k < n && one_kind_; ++k) note_kind(k);
  plane_xi_.assign(n * s_.planes.size(), Vec3::Zero());
  rest_planes_ = s_.planes;
  plane_v_.assign(s_.planes.size(), Vec3::Zero());
  s_.plane_motion.resize(s_.planes.size());
  planes_move_ = std::any_of(s_.plane_motion.begin(), s_.plane_motion.end(),
                             [](const Motion3& m) { return m.active(); });
  spring_at_.clear(), springs_.clear(), springs_used_ = 0;
  cells_ = SphereCells();
  if (s_.periodic_x) cells_.set_period(0, s_.periodic_x->first, s_.periodic_x->second);
  if (s_.periodic_y) cells_.set_period(1, s_.periodic_y->first, s_.periodic_y->second);
  pending_kick_ = false, moved_ = true, prediction_ = Prediction::unknown;
}

void SphereBed::note_kind(std::size_t slot) {
  const SphereKind k{m_[slot], inv_m_[slot], inv_i_[slot], r_[slot]};
  if (std::memcmp(&k, &kind_, sizeof k) != 0) one_kind_ = false;  // (bits: 0 and -0 are two kinds)
}

std::size_t SphereBed::slot_of(std::int64_t id) const {
  const auto it = std::lower_bound(id_.begin(), id_.end(), id);
  if (it == id_.end() || *it != id) throw std::runtime_error(fmt::format("body {} is not in the bed", id));
  return static_cast<std::size_t>(it - id_.begin());
}

// ---------------------------------------------------------------- stepping

// The work of one step on one sphere, specialised on the effects in play: drift (the pending half kick,
// this step's half kick and drift, the forces reset to gravity) and row (its listed pairs, in the
// orientation of its lower id, then its planes; then where the next drift will take it).
template <bool Friction, bool Rotation, bool Periodic, bool Uniform>
struct SphereBed::Kernel {
  static constexpr bool kRotation = Rotation;
  SphereBed& bed;
  Vec3* __restrict x, * __restrict v, * __restrict w, * __restrict f, * __restrict tq;
  Quat* __restrict q;
  // The spheres' constants: the bed's one kind (Uniform), or each slot's from the arrays.
  const SphereKind* one;
  const double* __restrict m_slots, * __restrict inv_m_slots, * __restrict inv_i_slots, * __restrict radii;
  // The four as arrays, made where they are used.
  KindColumn<&SphereKind::m, Uniform> masses() const { return {one, m_slots}; }
  KindColumn<&SphereKind::inv_m, Uniform> inverse_masses() const { return {one, inv_m_slots}; }
  KindColumn<&SphereKind::inv_i, Uniform> inverse_inertias() const { return {one, inv_i_slots}; }
  KindColumn<&SphereKind::r, Uniform> radius() const { return {one, radii}; }
  const std::int32_t* __restrict mat;
  const SphereCells::Index* __restrict list;
  std::uint32_t* __restrict spring_at;
  Vec3* __restrict springs;
  std::uint32_t* springs_used;
  const Vec3* __restrict x0;          // where the lists were built (nullptr: not built)
  const std::uint8_t* ghost;          // per slot, distributed beds only (nullptr: every slot is this rank's)
  const SphereCells::Index* offsets;  // where each slot's list entries start
  const std::uint32_t *plane_start, *plane_of;
  Vec3* plane_xi;
  std::size_t np;
  const ContactLaw* laws;
  int nm;
  PairBatch* batch;
  double dt, h, hs;  // step, half step, the shear springs' increment (0 at the very first evaluation)
  D3 g;
  std::size_t contacts = 0;
  double moved = 0;  // the largest squared displacement from the build positions (after drift or predicted)

  Kernel(SphereBed& b, double shear_step)
      : bed(b),
        x(b.x_.data()),
        v(b.v_.data()),
        w(b.w_.data()),
        f(b.f_.data()),
        tq(b.tq_.data()),
        q(b.q_.data()),
        one(&b.kind_),
        m_slots(b.m_.data()),
        inv_m_slots(b.inv_m_.data()),
        inv_i_slots(b.inv_i_.data()),
        radii(b.r_.data()),
        mat(b.mat_.data()),
        list(b.cells_.entries() ? b.cells_.begin(0) : nullptr),
        spring_at(b.spring_at_.data()),
        springs(b.springs_.data()),
        springs_used(&b.springs_used_),
        x0(b.cells_.builds() && b.cells_.build_positions().size() == b.x_.size()
               ? b.cells_.build_positions().data()
               : nullptr),
        ghost(b.ghost_.empty() ? nullptr : b.ghost_.data()),
        offsets(b.cells_.builds() ? b.cells_.offsets() : nullptr),
        plane_start(b.plane_start_.data()),
        plane_of(b.plane_of_.data()),
        plane_xi(b.plane_xi_.data()),
        np(b.s_.planes.size()),
        laws(b.s_.laws.data()),
        nm(b.s_.n_mat),
        batch(&b.batch_),
        dt(b.s_.dt),
        h(b.s_.dt / 2),
        hs(shear_step),
        g(get(b.s_.gravity)) {}

  // A pair in contact: the place of list entry k's spring, a fresh one (at zero) at the pair's first
  // touch since the build.
  [[gnu::always_inline]] std::uint32_t touch(std::size_t k) const {
    std::uint32_t at = spring_at[k];
    if (at & kTouching) [[likely]]
      return at & ~kTouching;
    if (at == kNoSpring) at = (*springs_used)++, springs[at].setZero();
    spring_at[k] = at | kTouching;
    return at;
  }
  // Apart: the spring goes (a pair apart has none, so its place keeps a zero).
  [[gnu::always_inline]] void part(std::size_t k) const {
    const std::uint32_t at = spring_at[k];
    if (at & kTouching) {
      spring_at[k] = at & ~kTouching;
      if (Friction) springs[at & ~kTouching].setZero();
    }
  }

  // An isotropic body's angular momentum I w + h tq turned back into w is w + h tq / I.
  // (Each unit copies what it uses into locals: a store through one of the arrays could otherwise, as far
  // as the compiler knows, change the members, which it would then reload after every store.)
  // Turn false: the orientation is left for turn4 (nothing reads it before the step ends).
  template <bool Complete, bool Turn = true>
  [[gnu::always_inline]] void drift(std::size_t i) const {
    Vec3* __restrict x = this->x, * __restrict v = this->v, * __restrict w = this->w, * __restrict f = this->f, * __restrict tq = this->tq;
    const double h = this->h, dt = this->dt;
    // The sphere's constants, read before any store (after one, the compiler would read them again).
    const double im = inverse_masses()[i], ii = inverse_inertias()[i], mi = masses()[i];
    const D3 fi = get(f[i]);
    D3 vi = get(v[i]);
    if constexpr (Complete) vi = half_kicked(vi, fi, im, h);
    vi = half_kicked(vi, fi, im, h);
    const D3 xi = drifted(get(x[i]), vi, dt);
    put(v[i], vi), put(x[i], xi);
    if constexpr (Rotation) {
      const D3 ti = get(tq[i]);
      D3 wi = get(w[i]);
      if constexpr (Complete) wi = half_kicked(wi, ti, ii, h);
      wi = half_kicked(wi, ti, ii, h);
      put(w[i], wi);
      if (Turn && nonzero(wi)) q[i] = detail3d::turned(q[i], w[i], dt);
      tq[i].setZero();
    }
    put(f[i], mi * g);
  }
  [[gnu::always_inline]] void note_moved(std::size_t i) {
    const D3 by = get(x[i]) - get(x0[i]);
    moved = std::max(moved, dot(by, by));
  }
  // Where the next drift will take sphere i, now that its force is final (later rows add only to later
  // slots): the same operations drift will do, so the same bits.
  [[gnu::always_inline]] void predict(std::size_t i) {
    const D3 fi = get(f[i]);
    const double im = inverse_masses()[i];
    const D3 v_next = half_kicked(half_kicked(get(v[i]), fi, im, h), fi, im, h);
    const D3 by = drifted(get(x[i]), v_next, dt) - get(x0[i]);
    moved = std::max(moved, dot(by, by));
  }

  // Whether sphere i (centre pi, radius ri) is clear of the plane in its plane slot c: then the plane's
  // spring goes. Otherwise `depth` is how deep i is in it.
  [[gnu::always_inline]] bool clear_of_plane(std::size_t i, std::size_t c, const D3& pi, double ri,
                                             double& depth) const {
    const Plane3& p = bed.s_.planes[plane_of[c]];
    depth = ri - dot(get(p.normal), pi - get(p.point));
    if (depth > 0) return false;
    forget(plane_xi[i * np + plane_of[c]]);
    return true;
  }
  // Sphere i's planes in its slots [c, c_end), added to its sums fi and ti; `tested`: slot c is in contact
  // at depth_c, as the caller's scan found. Returns the contacts.
  [[gnu::always_inline]] std::size_t plane_contacts(std::size_t i, std::size_t c, std::size_t c_end,
                                                    bool tested, double depth_c, const D3& pi, double ri,
                                                    double mi, const ContactLaw* row_laws, const D3& vi,
                                                    const D3& wi, D3& fi, D3& ti) const {
    std::size_t contacts = 0;
    double depth = depth_c;
    for (bool first = tested; c < c_end; ++c, first = false) {
      if (!first && clear_of_plane(i, c, pi, ri, depth)) continue;
      const std::size_t kp = plane_of[c];
      const D3 pn = get(bed.s_.planes[kp].normal);
      Vec3& spring = plane_xi[i * np + kp];
      const D3 ra = -pn * (ri - depth / 2);
      D3 vrel = vi - get(bed.plane_v_[kp]);  // (a plane at rest: exactly vi)
      if constexpr (Rotation) vrel = vrel + cross(wi, ra);
      const double vn = dot(pn, vrel);
      const ContactLaw& law = row_laws[bed.s_.plane_material[kp]];
      const double fn = normal_force(law, depth, vn, law.normal.coefficient(mi));
      D3 F = fn * pn;
      if constexpr (Friction) {
        D3 xi = get(spring);
        F = F + shear_force_3d(law, xi, pn, vrel - vn * pn, hs, mi, fn);
        put(spring, xi);
      }
      fi = fi + F;
      if constexpr (Rotation) ti = ti + cross(ra, F);
      ++contacts;
    }
    return contacts;
  }

  // The rows of a bed of one material (serial, or a rank's plain run of its own spheres' rows), a block
  // at a time: the scan finds the block's touching
  // pairs, batch_forces computes them four at a time, and each row then adds up its pairs and its planes
  // in row() order (the same bits). Rows [a, e), as many as the batch holds (a row longer than the batch
  // goes alone through row()); returns the first row not done. Every partner of the rows has drifted.
  // Mixed: a distributed bed's rows, among which ghosts' rows (GhostRow below) are taken in their place
  // in the order of rows, so every sum gets its terms in the order one rank adds them.
  static constexpr std::size_t kBlockRows = 32;
  template <bool Mixed = false>
  [[gnu::always_inline]] std::size_t block(std::size_t a, std::size_t e) {
    const Vec3* __restrict x = this->x;
    Vec3* __restrict f = this->f, * __restrict tq = this->tq;
    const auto r = radius();
    const auto m = masses();
    const SphereCells::Index* __restrict list = this->list;
    const SphereCells::Index* __restrict offsets = this->offsets;
    PairBatch& b = *batch;
    b.n = 0;
    std::uint32_t starts[kBlockRows + 1];
    std::size_t i = a;
    for (; i < e && b.fits(offsets[i + 1] - offsets[i]); ++i) {
      starts[i - a] = static_cast<std::uint32_t>(b.n);
      if (Mixed && ghost[i]) continue;
      const D3 pi = get(x[i]);
      const double ri = r[i];
      for (std::size_t k = offsets[i]; k < offsets[i + 1]; ++k) {
        const std::size_t j = list[k];
        D3 d = pi - get(x[j]);
        if constexpr (Periodic) {
          double dx = d.x(), dy = d.y();
          bed.cells_.to_nearest_image(dx, dy);
          d.xy = Pair{dx, dy};
        }
        const double reach = ri + r[j], r2 = dot(d, d);
        if (r2 < reach * reach && r2 != 0) {  // (as sphere_sphere: depth > 0, not coincident)
          b.add(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), touch(k), d.x(), d.y(), d.z, r2,
                reach);
        } else {
          part(k);
        }
      }
    }
    if (i == a) {
      if (Mixed && ghost[a])
        ghost_row(*this, a);
      else
        row<false>(a);
      return a + 1;
    }
    starts[i - a] = static_cast<std::uint32_t>(b.n);
    batch_forces<Friction, Rotation>(b, laws[0], hs, v, w, m, r, springs);
    const double* __restrict F[3] = {b[PairBatch::fx], b[PairBatch::fy], b[PairBatch::fz]};
    const double* __restrict TA[3] = {b[PairBatch::tax], b[PairBatch::tay], b[PairBatch::taz]};
    const double* __restrict TB[3] = {b[PairBatch::tbx], b[PairBatch::tby], b[PairBatch::tbz]};
    for (std::size_t own = a; own < i; ++own) {
      if (Mixed && ghost[own]) {
        ghost_row(*this, own);
        continue;
      }
      const std::size_t c0 = starts[own - a], c1 = starts[own - a + 1];
      const std::size_t p0 = plane_start[own], p1 = plane_start[own + 1];
      if (c0 != c1 || p0 != p1) {
        D3 fi = get(f[own]), ti = Rotation ? get(tq[own]) : D3{0, 0, 0};
        for (std::size_t c = c0; c < c1; ++c) {
          const D3 Fc{F[0][c], F[1][c], F[2][c]};
          const std::size_t j = b.j[c];
          fi = fi + Fc;
          put(f[j], get(f[j]) - Fc);
          if constexpr (Rotation) {
            ti = ti + D3{TA[0][c], TA[1][c], TA[2][c]};
            put(tq[j], get(tq[j]) - D3{TB[0][c], TB[1][c], TB[2][c]});
          }
        }
        contacts += c1 - c0;
        if (p0 != p1) {
          const D3 vi = get(v[own]), wi = Rotation ? get(w[own]) : D3{0, 0, 0};
          contacts +=
              plane_contacts(own, p0, p1, false, 0, get(x[own]), r[own], m[own], laws, vi, wi, fi, ti);
        }
        put(f[own], fi);
        if constexpr (Rotation) put(tq[own], ti);
      }
      if (x0) predict(own);
    }
    return i;
  }

  // A ghost's row, kept out of the sweep's loop (few rows are ghosts'; inlined, it would crowd out the
  // rest). It works on a copy of the kernel: were the sweep's kernel passed by address, the compiler would
  // keep that kernel in memory, and spill its running maximum of the displacement, through every row.
  [[gnu::noinline]] static void ghost_row(Kernel k, std::size_t i) { k.template row<true>(i); }
  // A ghost's row (GhostRow) computes only its pairs with this rank's spheres, and has no planes.
  template <bool GhostRow>
  [[gnu::always_inline]] void row(std::size_t i) {
    const Vec3* __restrict x = this->x, * __restrict v = this->v, * __restrict w = this->w;
    Vec3* __restrict f = this->f, * __restrict tq = this->tq, * __restrict springs = this->springs;
    const auto m = masses();
    const auto r = radius();
    const std::int32_t* __restrict mat = this->mat;
    const SphereCells::Index* __restrict list = this->list;
    const SphereCells::Index* __restrict offsets = this->offsets;
    const std::uint32_t* __restrict plane_start = this->plane_start;
    const double hs = this->hs;
    std::size_t contacts = 0;
    const D3 pi = get(x[i]);
    const double ri = r[i], mi = m[i];
    const ContactLaw* row_laws = laws + mat[i] * nm;
    // Entries apart cost a distance test (in a bed in flight, rows touch nothing). At the row's first
    // contact i's velocities and sums are read; they stay in registers through the rest of the row:
    // nothing else adds to i meanwhile.
    D3 d{0, 0, 0};
    double reach = 0, r2 = 0;
    auto apart = [&](std::size_t k, std::size_t j) __attribute__((always_inline)) {
      d = pi - get(x[j]);
      if constexpr (Periodic) {
        double dx = d.x(), dy = d.y();
        bed.cells_.to_nearest_image(dx, dy);
        d.xy = Pair{dx, dy};
      }
      reach = ri + r[j], r2 = dot(d, d);
      if (r2 < reach * reach && r2 != 0) return false;  // (as sphere_sphere: depth > 0, not coincident)
      part(k);
      return true;
    };
    double depth_p = 0;
    auto plane_apart = [&](std::size_t c) __attribute__((always_inline)) {
      return clear_of_plane(i, c, pi, ri, depth_p);
    };
    std::size_t k = offsets[i], c = plane_start[i];
    const std::size_t end = offsets[i + 1], c_end = plane_start[i + 1];
    for (; k < end; ++k)
      if (!(GhostRow && ghost[list[k]]) && !apart(k, list[k])) break;
    const bool planes_scanned = k == end;  // then c is at the first plane in contact, depth_p its depth
    if (planes_scanned)
      for (; c < c_end; ++c)
        if (!plane_apart(c)) break;
    if (k == end && c == c_end) {
      if (!GhostRow && x0) predict(i);
      return;
    }
    const D3 vi = get(v[i]), wi = Rotation ? get(w[i]) : D3{0, 0, 0};
    D3 fi = get(f[i]), ti = Rotation ? get(tq[i]) : D3{0, 0, 0};
    for (bool first = true; k < end; ++k, first = false) {
      const std::size_t j = list[k];
      if constexpr (GhostRow)
        if (ghost[j]) continue;             // neither sphere is this rank's: their owners compute the pair
      if (!first && apart(k, j)) continue;  // (the first was tested by the scan)
      [[maybe_unused]] const std::uint32_t place = touch(k);
      const double dist = std::sqrt(r2), depth = reach - dist;
      const D3 nrm = d / dist;
      // The contact point lies r_i - depth / 2 from i's centre, against the normal (which points j to i).
      const D3 ra = -nrm * (ri - depth / 2), rb = ra + d;
      D3 vrel;
      if constexpr (Rotation)
        vrel = (vi + cross(wi, ra)) - (get(v[j]) + cross(get(w[j]), rb));
      else
        vrel = vi - get(v[j]);
      const double vn = dot(nrm, vrel);
      const double mj = m[j], meff = mi * mj / (mi + mj);
      const ContactLaw& law = row_laws[mat[j]];
      const double fn = normal_force(law, depth, vn, law.normal.coefficient(meff));
      D3 F = fn * nrm;
      if constexpr (Friction) {
        Vec3& spring = springs[place];
        D3 xi = get(spring);
        F = F + shear_force_3d(law, xi, nrm, vrel - vn * nrm, hs, meff, fn);
        put(spring, xi);
      }
      fi = fi + F;
      put(f[j], get(f[j]) - F);
      if constexpr (Rotation) {
        ti = ti + cross(ra, F);
        put(tq[j], get(tq[j]) - cross(rb, F));
      }
      if (!GhostRow) ++contacts;  // (a pair with a ghost is counted by the rank of its lower id)
    }
    contacts += plane_contacts(i, c, c_end, planes_scanned, depth_p, pi, ri, mi, row_laws, vi, wi, fi, ti);
    put(f[i], fi);
    if constexpr (Rotation) put(tq[i], ti);
    this->contacts += contacts;
    if (!GhostRow && x0) predict(i);
  }
};

// Calls fn with a Kernel specialised on this bed's effects.
template <class Fn>
void SphereBed::with_kernel(double shear_step, Fn&& fn) {
  const bool periodic = s_.periodic_x || s_.periodic_y;
  // Beds of one kind of sphere (every bench bed, most scenes) with friction and rotation read their
  // constants from registers; the other combinations take the general kernel only (compile time).
  const bool uniform = one_kind_;
  auto run = [&](auto friction, auto rotation, auto periodic_sides, auto one_kind) {
    Kernel<decltype(friction)::value, decltype(rotation)::value, decltype(periodic_sides)::value,
           decltype(one_kind)::value>
        k(*this, shear_step);
    fn(k);
  };
  using T = std::true_type;
  using F = std::false_type;
  auto by_periodic = [&](auto friction, auto rotation) {
    auto by_kind = [&](auto periodic_sides) {
      if constexpr (decltype(friction)::value && decltype(rotation)::value)
        if (uniform) return run(friction, rotation, periodic_sides, T{});
      run(friction, rotation, periodic_sides, F{});
    };
    periodic ? by_kind(T{}) : by_kind(F{});
  };
  if (s_.friction)
    s_.rotation ? by_periodic(T{}, T{}) : by_periodic(T{}, F{});
  else
    s_.rotation ? by_periodic(F{}, T{}) : by_periodic(F{}, F{});
}

// Moving planes to where they are at time t; the others stay where they are.
void SphereBed::place_planes(double t) {
  if (!planes_move_) return;
  for (std::size_t k = 0; k < s_.planes.size(); ++k) {
    s_.planes[k].point = rest_planes_[k].point + s_.plane_motion[k].shift(t);
    plane_v_[k] = s_.plane_motion[k].velocity(t);
  }
}

void SphereBed::step(bool first, double t) {
  if (first) {
    place_planes(t);
    const Vec3 g = s_.gravity;
    for (std::size_t i = 0; i < x_.size(); ++i) f_[i] = m_[i] * g, tq_[i].setZero();
    forces(0);
  }
  place_planes(t + s_.dt);
  const bool complete = pending_kick_;
  ++steps_;
  if (recut_now_) prediction_ = Prediction::moves;  // a re-cut needs a rebuild: drift all, then rebuild
  with_kernel(s_.dt, [&](auto& k) {
    const bool predicted = prediction_ == Prediction::stays || prediction_ == Prediction::asked;
    if (s_.contacts && predicted && sweep_allowed_) {
      pipelined(k, complete);
    } else {
      complete ? drift_all<true>(k) : drift_all<false>(k);
      forces_with(k);
    }
  });
  ++evaluations_;
  pending_kick_ = true;
}

// One sweep: sphere t drifts, then the row of sphere t - L, L one more than the largest slot distance
// of a listed pair. Every partner of a row has drifted (and had its force reset) before the row reads or
// adds to it, and no row adds to a sphere before its drift: the same operations as drifting all and then
// running all rows, so the same bits, with each sphere's data still in cache when its row comes.
//
// Distributed, the spheres other ranks hold as ghosts drift first and are sent; the sweep then skips them
// and the ghosts (whose rows compute only their pairs with this rank's spheres).
template <class K>
void SphereBed::pipelined(K& kernel, bool complete) {
  K k = kernel;  // a local copy the compiler can keep in registers
  const std::size_t lag = lag_ + 1;
  if (domain_) {
    for (std::uint32_t i : sent_once_) complete ? k.template drift<true>(i) : k.template drift<false>(i);
    const bool rebuild_due = update_ghosts(moves_here_) && prediction_ == Prediction::asked;
    if (rebuild_due) {  // as drift_all and forces_with would, less the spheres already drifted and sent
      for (std::size_t i = 0; i < x_.size(); ++i)
        if (!not_swept_[i]) complete ? k.template drift<true>(i) : k.template drift<false>(i);
      moved_ = true;
      forces_with(kernel);
      return;
    }
    // Timed only when balancing by time is on: otherwise no probe would ever read (and clear) the costs.
    const bool timed = balancing_by_time() && own_load_ > 0;
    const auto t0 = timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
    complete ? sweep_distributed<true>(k, lag) : sweep_distributed<false>(k, lag);
    if (timed)
      sweep_cost_.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
                            own_load_);
  } else {
    complete ? sweep<true>(k, lag) : sweep<false>(k, lag);
  }
  contacts_ = k.contacts;
  if (domain_ && flag_rides_) {  // the answer rides on the next ghost update
    moves_here_ = k.moved > limit2();
    prediction_ = Prediction::asked;
  } else {
    prediction_ = any_rank(k.moved > limit2()) ? Prediction::moves : Prediction::stays;
  }
  if (domain_) probe_balance();
}

// The turns of slots [a, a + 8), left by the drifts for here: two independent groups of four, whose
// dependent chains of multiplications overlap (6-8 % less on the poured beds than one group at a time).
// Mixed: only the slots that drifted in the sweep (not skipped), one at a time in a group with a skipped
// slot (the same bits as four at a time).
template <bool Mixed>
void SphereBed::turn_eight(std::size_t a, const std::uint8_t* skip) {
  for (std::size_t g = a; g < a + 8; g += 4) {
    if (!Mixed || !(skip[g] | skip[g + 1] | skip[g + 2] | skip[g + 3])) {
      detail3d::turn4(&q_[g], &w_[g], s_.dt);
      continue;
    }
    for (std::size_t i = g; i < g + 4; ++i)
      if (!skip[i]) q_[i] = detail3d::turned(q_[i], w_[i], s_.dt);
  }
}

// The rows in blocks (the rows below t + 1 - lag have all their partners drifted) where they touch: a
// block's rows take a second pass to add up, which in a bed in flight, where nothing touches, costs
// more than the scan (the 10,000-sphere lattice as specified, 0.33 s by rows against 0.43 s in
// blocks). A quarter of a contact a sphere at the last evaluation decides; both give the same bits.
// Mixed: a distributed bed's sweep. Its ghosts and spheres sent (skip) do not drift here, and its ghosts'
// rows go in their place among the blocks' rows. A rank's own slots come in short runs where ids do not
// follow the cut (a poured bed numbered x fastest, cut along x: runs of some 25 slots), and before, every
// row outside a run went one pair at a time.
template <bool Complete, bool Mixed, class K>
void SphereBed::sweep_blocks(K& kernel, std::size_t lag, const std::uint8_t* skip) {
  K k = kernel;  // a local copy the compiler can keep in registers
  constexpr std::size_t B = K::kBlockRows;
  const std::size_t n = x_.size();
  std::size_t done = 0;
  for (std::size_t t = 0; t < n; ++t) {
    if (!Mixed || !skip[t]) k.template drift<Complete, !K::kRotation>(t);
    if (K::kRotation && t % 8 == 7) turn_eight<Mixed>(t - 7, skip);
    while (t + 1 >= lag + done + B) done = k.template block<Mixed>(done, done + B);
  }
  if constexpr (K::kRotation)
    for (std::size_t i = n - n % 8; i < n; ++i)
      if (!Mixed || !skip[i]) q_[i] = detail3d::turned(q_[i], w_[i], s_.dt);
  while (done < n) done = k.template block<Mixed>(done, std::min(n, done + B));
  kernel.contacts = k.contacts, kernel.moved = k.moved;
}

// Drift sphere t, then the row of sphere t - lag, for every t.
template <bool Complete, class K>
void SphereBed::sweep(K& kernel, std::size_t lag) {
  K k = kernel;  // a local copy the compiler can keep in registers (no lambdas: all of it inlined)
  const std::size_t n = x_.size(), head = std::min(lag, n);
  if (blocks_pay(k)) {  // where they touch, the rows in blocks
    sweep_blocks<Complete, false>(kernel, lag, nullptr);
    return;
  }
  for (std::size_t t = 0; t < head; ++t) k.template drift<Complete>(t);
  for (std::size_t t = head; t < n; ++t) {
    k.template drift<Complete>(t);
    k.template row<false>(t - lag);
  }
  for (std::size_t i = n - std::min(n, lag); i < n; ++i) k.template row<false>(i);
  kernel.contacts = k.contacts, kernel.moved = k.moved;
}

// The same on a distributed bed: ghosts and spheres already sent do not drift here, and a ghost's row
// takes only its pairs with this rank's spheres. Between those, the plain runs are swept as a serial bed
// is, without a test per slot: a rank's slots come in runs (ids are laid out along x, or at random in a
// poured bed), and the tests cost a serial sweep's time 15-20 % more.
template <bool Complete, class K>
void SphereBed::sweep_distributed(K& kernel, std::size_t lag) {
  K k = kernel;  // a local copy the compiler can keep in registers
  const std::uint8_t* __restrict skip = not_swept_.data();
  const std::uint8_t* __restrict ghost = ghost_.data();
  const std::size_t n = x_.size();
  auto any_row = [&](std::size_t i) __attribute__((always_inline)) {
    if (ghost[i])
      K::ghost_row(k, i);
    else
      k.template row<false>(i);
  };
  auto tested = [&](std::size_t t) __attribute__((always_inline)) {
    if (!skip[t]) k.template drift<Complete>(t);
    if (t >= lag) any_row(t - lag);
  };
  if (blocks_pay(k)) {  // where they touch, every row in blocks, the ghosts' among them
    sweep_blocks<Complete, true>(kernel, lag, skip);
    return;
  }
  std::size_t t = 0;
  for (const auto& [first, last] : plain_runs_) {
    for (; t < first; ++t) tested(t);
    for (; t < last; ++t) {
      k.template drift<Complete>(t);
      k.template row<false>(t - lag);
    }
  }
  for (; t < n; ++t) tested(t);
  for (std::size_t i = n - std::min(n, lag); i < n; ++i) any_row(i);
  kernel.contacts = k.contacts, kernel.moved = k.moved;
}

template <bool Complete, class K>
void SphereBed::drift_all(K& kernel) {
  K k = kernel;  // a local copy the compiler can keep in registers
  const std::size_t n = x_.size();
  if (k.ghost) {  // a ghost moves with its owner's data, sent each step
    for (std::size_t i = 0; i < n; ++i)
      if (!k.ghost[i]) {
        k.template drift<Complete>(i);
        if (k.x0) k.note_moved(i);
      }
  } else if (k.x0) {
    for (std::size_t i = 0; i < n; ++i) k.template drift<Complete>(i), k.note_moved(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) k.template drift<Complete>(i);
  }
  moved_ = any_rank(!k.x0 || k.moved > limit2()) || recut_now_;
}

// The rows, after a rebuild if some sphere has moved half the skin since the last one.
template <class K>
void SphereBed::forces_with(K& k) {
  contacts_ = 0;
  if (!s_.contacts || x_.empty()) {
    prediction_ = Prediction::unknown;
    return;
  }
  if (moved_) {
    rebuild();
    with_kernel(k.hs, [&](auto& fresh) { rows(fresh); });  // the lists' arrays have moved
  } else {
    if (domain_) update_ghosts();
    rows(k);
  }
}

template <class K>
void SphereBed::rows(K& kernel) {
  K k = kernel;  // a local copy the compiler can keep in registers
  if (k.ghost) {
    for (std::size_t i = 0; i < x_.size(); ++i) k.ghost[i] ? K::ghost_row(k, i) : k.template row<false>(i);
  } else {
    for (std::size_t i = 0; i < x_.size(); ++i) k.template row<false>(i);
  }
  contacts_ = k.contacts;
  prediction_ = any_rank(!k.x0 || k.moved > limit2()) ? Prediction::moves : Prediction::stays;
}

void SphereBed::forces(double h) {
  ++evaluations_;
  with_kernel(h, [&](auto& k) { forces_with(k); });
}

void SphereBed::finish() {
  if (!pending_kick_) return;
  const double h = s_.dt / 2;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    put(v_[i], half_kicked(get(v_[i]), get(f_[i]), inv_m_[i], h));
    if (s_.rotation) put(w_[i], half_kicked(get(w_[i]), get(tq_[i]), inv_i_[i], h));
  }
  pending_kick_ = false;
}

// ---------------------------------------------------------------- lists

// Spheres that crossed a periodic side come back in on the other (only at rebuilds, so a list's
// displacements stay continuous between builds).
void SphereBed::wrap_periodic() {
  for (const auto& [axis, period] : {std::make_pair(0, s_.periodic_x), std::make_pair(1, s_.periodic_y)})
    if (period)
      for (Vec3& p : x_) {
        const double L = period->second - period->first;
        p[axis] -= L * std::floor((p[axis] - period->first) / L);
      }
}

// New neighbour lists; the springs held move to their pairs' new entries.
void SphereBed::rebuild() {
  wrap_periodic();
  std::vector<SphereSpring> held = held_springs();
  if (domain_) exchange_spheres(held);
  cells_.build(x_, max_radius_, skin_, in_place_.empty() ? nullptr : in_place_.data());
  // The planes each sphere can reach before the next rebuild (it moves less than half the skin): most
  // of a bed's spheres touch none of them, and then test none. A ghost's planes are its owner's business,
  // and a sphere held in place needs none.
  plane_start_.assign(1, 0), plane_of_.clear();
  for (std::size_t i = 0; i < x_.size(); ++i) {
    const bool none = ghost(i) || (!in_place_.empty() && in_place_[i]);
    for (std::size_t k = 0; k < s_.planes.size() && !none; ++k)
      if (rest_planes_[k].normal.dot(x_[i] - rest_planes_[k].point) <
          r_[i] + skin_ + s_.plane_motion[k].reach())
        plane_of_.push_back(static_cast<std::uint32_t>(k));
    plane_start_.push_back(static_cast<std::uint32_t>(plane_of_.size()));
  }
  place_springs(std::move(held));
  lag_ = 0;
  for (std::size_t i = 0; i < x_.size(); ++i)
    if (cells_.end(i) != cells_.begin(i)) lag_ = std::max<std::size_t>(lag_, *(cells_.end(i) - 1) - i);
  plain_runs_.clear();
  if (domain_) {
    own_load_ = 0;  // as the re-cut weighs a sphere: 1 plus its listed pairs
    for (std::size_t i = 0; i < x_.size(); ++i)
      if (!ghost_[i]) own_load_ += 1.0 + double(cells_.end(i) - cells_.begin(i));
    // Runs shorter than this are left to the tested loop: entering a run costs about as much as the
    // tests it saves on a few slots.
    constexpr std::size_t kShortest = 4;
    const std::size_t lag = lag_ + 1, n = x_.size();
    for (std::size_t t = lag; t < n;) {
      std::size_t end = t;
      while (end < n && !not_swept_[end] && !ghost_[end - lag]) ++end;
      if (end - t >= kShortest)
        plain_runs_.emplace_back(static_cast<std::uint32_t>(t), static_cast<std::uint32_t>(end));
      t = end + 1;
    }
  }
  moved_ = false;
}

// Puts pair springs (sorted by ids, as the slots are) into the fresh lists by one merge per sphere. A
// held pair missing from the new lists (none is: a pair in contact is within their reach) is passed over.
void SphereBed::place_springs(std::vector<SphereSpring> held) {
  std::sort(held.begin(), held.end(), spring_order);
  held.erase(
      std::unique(held.begin(), held.end(),
                  [](const SphereSpring& p, const SphereSpring& q) { return p.a == q.a && p.b == q.b; }),
      held.end());
  const std::size_t np = s_.planes.size();
  plane_xi_.assign(x_.size() * np, Vec3::Zero());
  for (const SphereSpring& sp : held)
    if (sp.b < 0) {
      const auto it = std::lower_bound(id_.begin(), id_.end(), sp.a);
      if (it != id_.end() && *it == sp.a)
        plane_xi_[static_cast<std::size_t>(it - id_.begin()) * np - 1 - sp.b] = sp.xi;
    }
  if (cells_.entries() >= kNoSpring)  // (a place must stay clear of the flag and of kNoSpring)
    throw std::length_error("neighbour lists of 2^31 - 1 entries or more");
  spring_at_.assign(cells_.entries(), kNoSpring);
  springs_.resize(cells_.entries());  // (uninitialised: each place is set when it is taken)
  springs_used_ = 0;
  auto it = held.begin();
  const SphereCells::Index* list = cells_.begin(0);
  for (std::size_t i = 0; i < x_.size() && it != held.end(); ++i)
    for (std::size_t k = cells_.first(i); k < cells_.first(i + 1); ++k) {
      const std::int64_t a = id_[i], b = id_[list[k]];
      while (it != held.end() && (it->a < a || (it->a == a && (it->b < 0 || it->b < b)))) ++it;
      if (it != held.end() && it->a == a && it->b == b)
        spring_at_[k] = springs_used_ | kTouching, springs_[springs_used_++] = it->xi, ++it;
    }
}

// ---------------------------------------------------------------- state

std::vector<double> SphereBed::elastic_shares() const {
  std::vector<double> share(x_.size(), 0.0);
  if (x_.empty() || cells_.builds() == 0) return share;  // (no force evaluation yet: no contacts known)
  const std::size_t np = s_.planes.size();
  const SphereCells::Index* list = cells_.begin(0);
  for (std::size_t i = 0; i < x_.size(); ++i) {
    for (std::size_t k = cells_.first(i); k < cells_.first(i + 1); ++k) {
      const std::size_t j = list[k];
      const ContactLaw& law = s_.laws[mat_[i] * s_.n_mat + mat_[j]];
      const double depth = r_[i] + r_[j] - cells_.separation(x_[i], x_[j]).norm();
      double u = 0;
      if (depth > 0) u += 0.5 * law.k_n * depth * depth;
      if (s_.friction) u += 0.5 * law.k_s * pair_spring(k).squaredNorm();
      share[i] += 0.5 * u;
      share[j] += 0.5 * u;
    }
    for (std::size_t k = 0; k < np; ++k) {
      const ContactLaw& law = s_.laws[mat_[i] * s_.n_mat + s_.plane_material[k]];
      const double depth = r_[i] - s_.planes[k].normal.dot(x_[i] - s_.planes[k].point);
      if (depth > 0) share[i] += 0.5 * law.k_n * depth * depth;
      if (s_.friction) share[i] += 0.5 * law.k_s * plane_xi_[i * np + k].squaredNorm();
    }
  }
  return share;
}

// Every spring this rank holds by ids: pairs it computes (not two ghosts) and its spheres' planes.
std::vector<SphereSpring> SphereBed::held_springs() const {
  std::vector<SphereSpring> out;
  const std::size_t np = s_.planes.size();
  const SphereCells::Index* list = cells_.entries() ? cells_.begin(0) : nullptr;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    for (std::size_t k = cells_.builds() ? cells_.first(i) : 0; cells_.builds() && k < cells_.first(i + 1);
         ++k)
      if (holds(pair_spring(k)) && !(ghost(i) && ghost(list[k])))
        out.push_back({id_[i], id_[list[k]], pair_spring(k)});
    for (std::size_t k = 0; k < np && !ghost(i); ++k)
      if (holds(plane_xi_[i * np + k]))
        out.push_back({id_[i], -1 - static_cast<std::int64_t>(k), plane_xi_[i * np + k]});
  }
  return out;
}

std::vector<SphereSpring> SphereBed::springs() const {
  std::vector<SphereSpring> out = held_springs();
  std::sort(out.begin(), out.end(), spring_order);
  return out;
}

void SphereBed::restore(const std::vector<Vec3>& built_at, const std::vector<SphereSpring>& springs,
                        const Decomposition& decomposition) {
  if (built_at.size() != x_.size())
    throw std::runtime_error(fmt::format("{} build positions for {} spheres", built_at.size(), x_.size()));
  const std::vector<std::int64_t> all_ids = id_;
  const std::vector<Vec3> now = x_;
  x_ = built_at;
  cells_ = SphereCells();
  if (s_.periodic_x) cells_.set_period(0, s_.periodic_x->first, s_.periodic_x->second);
  if (s_.periodic_y) cells_.set_period(1, s_.periodic_y->first, s_.periodic_y->second);
  plane_xi_.assign(x_.size() * s_.planes.size(), Vec3::Zero());
  if (decomposition.distributed) distribute(decomposition);  // regions cut at the build positions
  rebuild();                                                 // a fresh build: no springs to carry
  for (std::size_t k = 0; k < x_.size(); ++k)
    x_[k] = now[static_cast<std::size_t>(std::lower_bound(all_ids.begin(), all_ids.end(), id_[k]) -
                                         all_ids.begin())];
  // The springs this rank holds: its spheres' planes, and pairs with one of its spheres (which must be
  // listed: they were when the state was saved).
  std::vector<SphereSpring> mine;
  auto here = [&](std::int64_t id) {
    const auto it = std::lower_bound(id_.begin(), id_.end(), id);
    return it != id_.end() && *it == id && !ghost(static_cast<std::size_t>(it - id_.begin()));
  };
  const std::size_t np = s_.planes.size();
  for (const SphereSpring& sp : springs) {
    if (sp.b < 0 && static_cast<std::size_t>(-1 - sp.b) >= np)
      throw std::runtime_error(fmt::format("a saved spring holds plane {} of {}", -1 - sp.b, np));
    if (!here(sp.a) && !(sp.b >= 0 && here(sp.b))) continue;
    if (sp.b >= 0) {
      const std::size_t i = slot_of(sp.a), j = slot_of(sp.b);
      const SphereCells::Index* at = std::lower_bound(cells_.begin(i), cells_.end(i), j);
      if (at == cells_.end(i) || *at != j)
        throw std::runtime_error(
            fmt::format("a saved spring joins bodies {} and {}, not listed as neighbours", sp.a, sp.b));
    }
    mine.push_back(sp);
  }
  place_springs(std::move(mine));
  pending_kick_ = false, moved_ = false, prediction_ = Prediction::unknown;
}

}  // namespace grainlab::dem
