// Force evaluation. The kernels are templates on the active effects, so a frictionless scene compiles
// to a loop with no shear-history traffic and no tangential arithmetic, and a non-rotating one never
// touches spins or torques (design principle: only the effects a scene calls for).
#include <chrono>
#include <cmath>

#include "narrow_phase.hpp"
#include "world.hpp"

namespace grainlab::dem {

namespace {
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
}  // namespace

// History key of a general (polygon or polygon-wall) contact, from stable ids: survives reordering
// and migration between ranks.
std::uint64_t World::general_key(std::int64_t a, std::int64_t b, int sub) {
  return mix64(static_cast<std::uint64_t>(a)) ^ mix64(static_cast<std::uint64_t>(b) * 31 + 7) ^
         mix64(static_cast<std::uint64_t>(sub) + 0x1234567ull);
}

class ForceKernels {
 public:
  // Disc pairs in two passes so that every particle sums its forces in one canonical order, whatever
  // the particles' memory order or the ranks' domains: (1) each listed pair's force is computed once, in
  // the orientation of its lower id, and stored; (2) each owned particle adds its pairs' forces in
  // ascending partner id. Pass 2 makes a dense bed bitwise reproducible on any number of ranks.
  template <bool Friction, bool Rotation, bool Periodic>
  static void disc_pairs(World& W, double h) {
    Particles& P = W.p_;
    World::PairList& L = W.discs_;
    const double *x = P.x.data(), *y = P.y.data(), *vx = P.vx.data(), *vy = P.vy.data(), *w = P.w.data();
    const double *r = P.r.data(), *im = P.inv_m.data();
    const std::int32_t* mat = P.mat.data();
    const std::uint32_t *off = L.offset.data(), *nb = L.j.data();
    const double* shift = L.shift.data();
    const double* xi_old = L.xi.data();
    double* xi_new = L.xi_new.data();
    double* pf = L.force.data();
    std::uint8_t* touching = L.touching.data();
    // Which particles touch anything: pass 2 skips the rest (most grains in flight touch nothing).
    L.particle_touching.assign(P.size(), 0);
    std::uint8_t* any = L.particle_touching.data();
    const ContactLaw* laws = W.laws_.data();
    const int nm = W.n_mat_;
    const std::size_t rows = L.offset.empty() ? 0 : L.offset.size() - 1;
    const bool track = static_cast<bool>(W.after_step_);
    for (std::size_t i = 0; i < rows; ++i) {
      const std::uint32_t kb = off[i], ke = off[i + 1];
      if (kb == ke) continue;
      const double xi = x[i], yi = y[i], ri = r[i], vxi = vx[i], vyi = vy[i], imi = im[i];
      const double wi = Rotation ? w[i] : 0.0;
      const ContactLaw* row = laws + mat[i] * nm;
      for (std::uint32_t k = kb; k < ke; ++k) {
        const std::uint32_t j = nb[k];
        double dx = xi - x[j];
        if constexpr (Periodic) dx += shift[k];
        const double dy = yi - y[j];
        const double rsum = ri + r[j];
        const double d2 = dx * dx + dy * dy;
        if (d2 >= rsum * rsum) {
          if constexpr (Friction) xi_new[k] = 0;  // contact open: the shear spring is released
          touching[k] = 0;                        // pass 2 skips it: no force to add
          continue;
        }
        const ContactLaw& law = row[mat[j]];
        const double dist = std::sqrt(d2);
        const double inv = 1.0 / dist;
        const double nx = dx * inv, ny = dy * inv;
        const double dvx = vxi - vx[j], dvy = vyi - vy[j];
        const double meff = 1.0 / (imi + im[j]);
        const double vn = dvx * nx + dvy * ny;
        const double fn = normal_force(law, rsum - dist, vn, law.normal.coefficient(meff));
        if (track) W.pair_force_[{P.id[i], P.id[j]}] += fn;
        double cfx = fn * nx, cfy = fn * ny;
        if constexpr (Friction) {
          // s with s x n = +z (eq. 2.3); v_s = s.(v_i - v_j) + r_i w_i + r_j w_j.
          const double sx = ny, sy = -nx;
          double vs = dvx * sx + dvy * sy;
          if constexpr (Rotation) vs += ri * wi + r[j] * w[j];
          double ext = xi_old[k];
          const double fs = shear_force(law, fn, vs, law.shear.coefficient(meff), h, ext);
          xi_new[k] = ext;
          cfx += fs * sx;
          cfy += fs * sy;
          if constexpr (Rotation) {
            pf[3 * k + 2] = fs;
          }
        } else if constexpr (Rotation) {
          pf[3 * k + 2] = 0;
        }
        pf[3 * k] = cfx;
        pf[3 * k + 1] = cfy;
        touching[k] = 1;
        any[i] = any[j] = 1;
      }
    }
    sum_disc_pairs<Rotation>(W);
  }

  // Pass 2: each owned particle's pair forces in ascending partner id (entry 2k: the row's particle
  // of pair k, 2k + 1: its partner, which takes the force negated; negation is exact).
  template <bool Rotation>
  static void sum_disc_pairs(World& W) {
    Particles& P = W.p_;
    const World::PairList& L = W.discs_;
    const std::uint32_t *io = L.inc_offset.data(), *inc = L.inc.data();
    const double* pf = L.force.data();
    const std::uint8_t* touching = L.touching.data();
    const std::uint8_t* any = L.particle_touching.data();
    double *fx = P.fx.data(), *fy = P.fy.data(), *tq = P.tq.data();
    const double* r = P.r.data();
    const std::size_t owned = L.inc_offset.empty() ? 0 : L.inc_offset.size() - 1;
    for (std::size_t i = 0; i < owned; ++i) {
      if (!any[i]) continue;
      double sx = fx[i], sy = fy[i], st = Rotation ? tq[i] : 0.0;
      const double ri = r[i];
      for (std::uint32_t e = io[i]; e < io[i + 1]; ++e) {
        const std::uint32_t code = inc[e], k = code >> 1;
        if (!touching[k]) continue;
        const double sign = (code & 1) ? -1.0 : 1.0;
        const double* f = pf + 3 * k;
        sx += sign * f[0];
        sy += sign * f[1];
        if constexpr (Rotation) st += ri * f[2];  // the shear force turns both discs the same way
      }
      fx[i] = sx;
      fy[i] = sy;
      if constexpr (Rotation) tq[i] = st;
    }
  }

  // One contact with lever arms: used for walls and polygons (few contacts, generality first).
  // j < 0 means a wall moving at `wall_v`; `other` is j's id or -1 - the wall's index.
  template <bool Friction, bool Rotation>
  static void apply(World& W, std::uint32_t i, long j, std::int64_t other, Vec2 wall_v,
                    const ContactGeometry& c, const ContactLaw& law, double h, const double* xi_committed,
                    double* xi_trial) {
    Particles& P = W.p_;
    const double inv_mj = j >= 0 ? P.inv_m[j] : 0.0;
    const double meff = 1.0 / (P.inv_m[i] + inv_mj);
    Vec2 vrel{P.vx[i], P.vy[i]};
    if (Rotation) vrel += spin_cross(P.w[i], c.arm_i);
    if (j >= 0) {
      vrel -= Vec2{P.vx[j], P.vy[j]};
      if (Rotation) vrel -= spin_cross(P.w[j], c.arm_j);
    } else {
      vrel -= wall_v;
    }
    const double fn = normal_force(law, c.depth, dot(vrel, c.normal), law.normal.coefficient(meff));
    if (W.after_step_) W.pair_force_[{P.id[i], other}] += fn;
    Vec2 F = c.normal * fn;
    if constexpr (Friction) {
      const Vec2 s{c.normal.y, -c.normal.x};
      double ext = xi_committed ? *xi_committed : 0.0;
      F += s * shear_force(law, fn, dot(vrel, s), law.shear.coefficient(meff), h, ext);
      *xi_trial = ext;
    }
    P.fx[i] += F.x;
    P.fy[i] += F.y;
    if (Rotation) P.tq[i] += cross(c.arm_i, F);
    if (j >= 0) {
      P.fx[j] -= F.x;
      P.fy[j] -= F.y;
      if (Rotation) P.tq[j] -= cross(c.arm_j, F);
    }
  }

  template <bool Friction, bool Rotation>
  static void disc_walls(World& W, double h) {
    Particles& P = W.p_;
    for (std::size_t wi = 0; wi < W.walls_.size(); ++wi) {
      const Wall& wall = W.walls_[wi];
      World::WallList& L = W.wall_lists_[wi];
      for (std::size_t k = 0; k < L.particle.size(); ++k) {
        const std::uint32_t i = L.particle[k];
        ContactGeometry c;
        if (!disc_wall_contact({P.x[i], P.y[i]}, P.r[i], wall, c)) {
          if constexpr (Friction) L.xi_new[k] = 0;
          continue;
        }
        const ContactLaw& law = W.laws_[P.mat[i] * W.n_mat_ + wall.spec.material];
        apply<Friction, Rotation>(W, i, -1, -1 - static_cast<std::int64_t>(wi), wall.velocity, c, law, h,
                                  Friction ? &L.xi[k] : nullptr, Friction ? &L.xi_new[k] : nullptr);
      }
    }
  }

  template <bool Friction, bool Rotation>
  static void general(World& W, double h) {
    Particles& P = W.p_;
    auto body = [&](std::uint32_t i) {
      return BodyPose{{P.x[i], P.y[i]}, P.th[i], P.r[i], P.shape[i] < 0 ? nullptr : &W.polygons_[P.shape[i]]};
    };
    auto run = [&](std::uint32_t i, long j, Vec2 wall_v, const ContactGeometry& c, const ContactLaw& law,
                   std::int64_t other_id, int sub) {
      double* trial = nullptr;
      const double* committed = nullptr;
      if constexpr (Friction) {
        const std::uint64_t key = World::general_key(P.id[i], other_id, sub);
        auto it = W.general_xi_.find(key);
        committed = it == W.general_xi_.end() ? nullptr : &it->second;
        trial = &W.general_xi_new_[key];
      }
      apply<Friction, Rotation>(W, i, j, other_id, wall_v, c, law, h, committed, trial);
    };
    if constexpr (Friction) W.general_xi_new_.clear();
    for (const World::GeneralPair& gp : W.general_pairs_) {
      ContactGeometry c;
      BodyPose a = body(gp.i), b = body(gp.j);
      a.centre.x += gp.shift;
      if (!body_body_contact(a, b, c, W.outline_a_, W.outline_b_)) continue;
      run(gp.i, gp.j, {}, c, W.laws_[P.mat[gp.i] * W.n_mat_ + P.mat[gp.j]], P.id[gp.j], 0);
    }
    for (std::uint32_t i : W.polygon_particles_)
      for (std::size_t wi = 0; wi < W.walls_.size(); ++wi) {
        const Wall& wall = W.walls_[wi];
        const ContactLaw& law = W.laws_[P.mat[i] * W.n_mat_ + wall.spec.material];
        const BodyPose pose = body(i);
        for (std::size_t v = 0; v < pose.vertices->size(); ++v) {
          ContactGeometry c;
          if (vertex_wall_contact(pose, v, wall, c))
            run(i, -1, wall.velocity, c, law, -1 - static_cast<std::int64_t>(wi), static_cast<int>(v));
        }
      }
  }

  template <bool Friction, bool Rotation>
  static void all_contacts(World& W, double h) {
    if (W.period_ > 0)
      disc_pairs<Friction, Rotation, true>(W, h);
    else
      disc_pairs<Friction, Rotation, false>(W, h);
    disc_walls<Friction, Rotation>(W, h);
    general<Friction, Rotation>(W, h);
  }
};

void World::compute_forces(double t, double shear_h, bool body_forces_ready) {
  const auto start = std::chrono::steady_clock::now();
  struct Stopwatch {  // charges the evaluation to seconds_forces on every exit path
    std::chrono::steady_clock::time_point t0;
    double& total;
    ~Stopwatch() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
  } watch{start, diag_.seconds_forces};
  ++diag_.force_evaluations;
  if (!ghosts_fresh_) update_ghosts();
  for (Wall& wall : walls_) wall.at(t);
  if (!body_forces_ready) {
    const std::size_t n = n_own_;
    const double gx = effects_.has(Effect::gravity) ? g_.x : 0.0,
                 gy = effects_.has(Effect::gravity) ? g_.y : 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      p_.fx[i] = p_.m[i] * gx;
      p_.fy[i] = p_.m[i] * gy;
    }
    if (effects_.has(Effect::rotation)) std::fill(p_.tq.begin(), p_.tq.begin() + static_cast<long>(n), 0.0);
  }
  if (wind_) {
    const auto w0 = std::chrono::steady_clock::now();
    wind_->add_drag(p_, n_own_);
    diag_.seconds_wind += std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  }
  pair_force_.clear();
  if (!effects_.has(Effect::normal_contact)) return;
  const bool f = effects_.has(Effect::friction), r = effects_.has(Effect::rotation);
  if (f && r)
    ForceKernels::all_contacts<true, true>(*this, shear_h);
  else if (f)
    ForceKernels::all_contacts<true, false>(*this, shear_h);
  else if (r)
    ForceKernels::all_contacts<false, true>(*this, shear_h);
  else
    ForceKernels::all_contacts<false, false>(*this, shear_h);
}

void World::commit_history() {
  if (!effects_.has(Effect::friction)) return;
  discs_.xi.swap(discs_.xi_new);
  for (WallList& L : wall_lists_) L.xi.swap(L.xi_new);
  general_xi_.swap(general_xi_new_);
}

}  // namespace grainlab::dem
