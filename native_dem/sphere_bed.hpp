#pragma once
// The 3-D engine's sphere kernel: a bed of spheres under velocity Verlet with the physics of the general
// path (world3d.cpp: step_verlet, compute_forces, add_contact), written for speed.
//
// - The hot fields live in arrays of their own, in slots sorted by body id. Every sphere adds its forces
//   in one canonical order (gravity, partners by ascending id, then planes), so a bed split over MPI ranks
//   (owned spheres plus ghost copies of the neighbours', also sorted by id) sums the same terms in the same
//   order as one process, and writes the same bits.
// - Each shear spring sits in a pool in the order its pair first touched since the lists were built (a
//   list entry holds a flag saying whether the pair touched at the last evaluation, and the spring's
//   place), or in its sphere's plane slot: pairs apart cost no spring traffic and no spring memory.
//   A spring at zero is the same as no spring.
// - A step makes two passes over the spheres instead of five: the second half kick of one step runs in
//   the same pass as the first half kick and drift of the next (the same operations on the same values,
//   so the same bits), together with the force reset and the list-staleness test; then the force loop.
//   The pending half kick is completed by finish() before anyone looks at the state.
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "contact_law.hpp"
#include "domain.hpp"
#include "narrow_phase3d.hpp"
#include "sphere_cells.hpp"
#include "sphere_pair_batch.hpp"
#include "world_types.hpp"

namespace grainlab::dem {

// What a sphere bed needs of its scene.
struct SphereBedSetup {
  std::vector<Plane3> planes;         // at rest
  std::vector<Motion3> plane_motion;  // per plane (fewer: the rest are at rest; load() fills them in)
  std::vector<int> plane_material;
  std::vector<ContactLaw> laws;  // [a * n_mat + b]
  int n_mat = 1;
  bool contacts = true, friction = true, rotation = true;
  Vec3 gravity = Vec3::Zero();
  double dt = 0;
  std::optional<std::pair<double, double>> periodic_x, periodic_y;
};

// One sphere's state as the bed takes it in and gives it back.
struct SphereState {
  std::int64_t id = 0;
  Vec3 x = Vec3::Zero(), v = Vec3::Zero(), w = Vec3::Zero(), f = Vec3::Zero(), tq = Vec3::Zero();
  Quat q = Quat::Identity();
  double m = 0, inv_i = 0, r = 0;  // inv_i: the isotropic inverse moment of inertia (0: no rotation)
  int material = 0;
  bool held = false;  // held in place (Body3Spec::held): never moves, pushes back with its mass m
};

// The constants of a sphere: its mass, inverse mass (0: held in place), isotropic inverse moment of
// inertia and radius. A bed whose spheres all have the same four (every bench bed, most scenes) is
// stepped by a kernel that keeps them in registers and reads none of the four arrays: 32 bytes a sphere
// fewer to stream, which on a settled bed of 100,000 spheres was part of the difference between a
// step's arrays fitting the 32 MB L3 cache or not (bench/README.md).
struct SphereKind {
  double m = 0, inv_m = 0, inv_i = 0, r = 0;
};
// One of the constants by slot: the bed's one kind's (Uniform), or the slot's own from its array.
template <double SphereKind::*Field, bool Uniform>
struct KindColumn {
  const SphereKind* one;
  const double* slots;
  double operator[](std::size_t slot) const {
    if constexpr (Uniform)
      return one->*Field;
    else
      return slots[slot];
  }
};

// A shear spring by body ids: b >= 0 another sphere (a < b), b < 0 plane -1 - b.
struct SphereSpring {
  std::int64_t a = 0, b = 0;
  Vec3 xi = Vec3::Zero();
};

// The order springs are kept and saved in: by a, then a's pairs by b, then its planes by index.
bool spring_order(const SphereSpring& p, const SphereSpring& q);

class SphereBed {
 public:
  // The neighbour lists' skin, as a share of the largest radius; a list reaches two radii and the skin.
  static constexpr double kSkinPerRadius = 0.2;
  // The spheres to step, in any order. `max_radius`: the largest radius of the whole bed (every rank's
  // share): it sets the skin, so every rank rebuilds its lists on the same steps.
  void load(const SphereBedSetup& setup, const std::vector<SphereState>& spheres, double max_radius);
  // One Verlet step. `first`: nothing has been evaluated yet, so the forces at the start come first.
  // One Verlet step from time t (the time moving planes are placed at; t + dt for the step's forces).
  void step(bool first, double t);
  // Tests: false makes every step take two passes (drift all, then all rows), as after a list rebuild.
  void allow_sweep(bool on) { sweep_allowed_ = on; }
  // Completes the last step's second half kick (a no-op if none is pending).
  void finish();
  // Spreads the bed over the MPI ranks (sphere_bed_parallel.cpp). Every rank loaded the same spheres;
  // each keeps the slab (or grid cell, decomposition.ranks_y > 1) holding an equal share, and from the
  // first force evaluation on holds ghost copies of the other ranks' spheres near it. Each pair with a
  // ghost is computed by both ranks in the orientation of its lower id, each sphere sums its forces in
  // id order, and all ranks rebuild on the same steps: the results are those of one process, bit for bit.
  void distribute(const Decomposition& decomposition);
  bool distributed() const { return domain_.has_value(); }
  // Calls fn(const SphereState&) for this rank's own spheres in slot (id) order; only after finish().
  // (A visitor, not a vector: a fresh 2 MB vector for 10,000 spheres cost 6-15 ms of page faults here,
  // paid at every frame, against 0.25 s for 2,000 steps.)
  template <class Fn>
  void each_state(Fn&& fn) const;
  std::size_t size() const { return x_.size(); }
  bool ghost(std::size_t slot) const { return !ghost_.empty() && ghost_[slot]; }
  std::int64_t id(std::size_t slot) const { return id_[slot]; }
  // Force evaluations so far, and the contacts of the last one.
  std::uint64_t force_evaluations() const { return evaluations_; }
  std::size_t contacts() const { return contacts_; }
  std::uint64_t list_builds() const { return cells_.builds(); }
  // Distributed: how often the regions were re-cut to the ranks' measured speeds.
  std::uint64_t region_recuts() const { return recuts_; }

  // The elastic energy (normal and shear springs of pairs and planes) per sphere, half of each pair to
  // each partner, in slot order: the caller sums the shares in id order.
  std::vector<double> elastic_shares() const;
  // Springs held by this rank's spheres (pairs with a ghost included), sorted, and where the lists were
  // built (per slot), for checkpoints.
  std::vector<SphereSpring> springs() const;
  const std::vector<Vec3>& build_positions() const { return cells_.build_positions(); }
  // Continues a saved run: lists built at the saved build positions (so rebuilds and periodic wrapping
  // come on the same steps), then the springs put back. Throws std::runtime_error for a spring between
  // spheres that are not listed as neighbours there.
  // `built_at` and `springs` cover the whole bed, as loaded; a decomposition spreads it over the ranks
  // by the build positions.
  void restore(const std::vector<Vec3>& built_at, const std::vector<SphereSpring>& springs,
               const Decomposition& decomposition = {});

 private:
  template <bool Friction, bool Rotation, bool Periodic, bool Uniform>
  struct Kernel;
  template <class Fn>
  void with_kernel(double shear_step, Fn&& fn);
  template <class K>
  void pipelined(K& k, bool complete);
  template <bool Complete, class K>
  void drift_all(K& k);
  template <bool Complete, class K>
  void sweep(K& k, std::size_t lag);
  // Whether a sweep takes its rows in blocks of four-at-a-time pairs: one contact law, and at least a
  // quarter of a contact a sphere at the last evaluation (in flight, the blocks' second pass costs more
  // than it saves). Both ways give the same bits.
  template <class K>
  bool blocks_pay(const K& k) const {
    return k.nm == 1 && 4 * contacts_ >= x_.size();
  }
  template <bool Complete, class K>
  void sweep_distributed(K& k, std::size_t lag);
  template <bool Complete, bool Mixed, class K>
  void sweep_blocks(K& k, std::size_t lag, const std::uint8_t* skip);
  template <bool Mixed>
  void turn_eight(std::size_t a, const std::uint8_t* skip);
  template <class K>
  void forces_with(K& k);
  template <class K>
  void rows(K& k);
  void forces(double h);
  void rebuild();
  void wrap_periodic();
  std::vector<SphereSpring> held_springs() const;
  void place_springs(std::vector<SphereSpring> held);
  // Distributed (sphere_bed_parallel.cpp): at a rebuild, ghosts dropped, the regions re-cut when due,
  // spheres that left their region sent to their new owner with their springs, ghosts received, all
  // slots sorted by id again; and every step, the ghosts' positions and velocities from their owners.
  void exchange_spheres(std::vector<SphereSpring>& held);
  // Sends this rank's spheres that others hold as ghosts and takes in its own ghosts. When the flag
  // rides (see flag_rides_), each message also carries the sender's `moves_here`; the result is then
  // whether any rank's was set (otherwise just `moves_here`).
  bool update_ghosts(bool moves_here = false);
  void sort_slots();
  // Every Decomposition::probe_every steps: the ranks' measured speeds, and a re-cut to them when due.
  void probe_balance();
  bool balancing_by_time() const {
    return decomposition_.balance_every > 0 && decomposition_.probe_every > 0;
  }
  bool any_rank(bool mine) const;
  std::size_t slot_of(std::int64_t id) const;
  double limit2() const { return 0.25 * skin_ * skin_; }

  SphereBedSetup s_;
  double skin_ = 0, max_radius_ = 0;
  // Per slot (sorted by id).
  std::vector<std::int64_t> id_;
  std::vector<Vec3> x_, v_, w_, f_, tq_;
  std::vector<Quat> q_;
  std::vector<double> m_, inv_m_, inv_i_, r_;
  // Whether every slot has the same four, to the bit, and which: set at load, cleared when a sphere of
  // another kind arrives from another rank.
  bool one_kind_ = false;
  SphereKind kind_;
  void note_kind(std::size_t slot);
  std::vector<std::int32_t> mat_;
  // Per slot, whether the sphere is held in place (empty: none is). Two held spheres are never listed as
  // a pair, and a held one tests no planes: only its pairs with free spheres are computed.
  std::vector<std::uint8_t> in_place_;
  // Per list entry: where its spring sits in springs_ (kNoSpring: it has not touched since the lists were
  // built) and, in the top bit (kTouching), whether the pair touched at the last evaluation. A pair takes
  // a place at its first touch and keeps it until the next build, so springs_ never holds more than the
  // entries, and holds the pairs that touch side by side: of a settled lattice's three entries a sphere
  // one touches, and the springs take 24 bytes a sphere instead of 72.
  static constexpr std::uint32_t kTouching = 0x80000000u, kNoSpring = 0x7fffffffu;
  std::vector<std::uint32_t> spring_at_;
  std::vector<Vec3> springs_;  // as long as the entries; the first springs_used_ are in use
  std::uint32_t springs_used_ = 0;
  Vec3 pair_spring(std::size_t entry) const {
    const std::uint32_t at = spring_at_[entry] & ~kTouching;
    return at == kNoSpring ? Vec3::Zero() : springs_[at];
  }
  // Per slot and plane: the spring; per slot, the planes it may reach before the next rebuild.
  std::vector<Vec3> plane_xi_;
  std::vector<std::uint32_t> plane_start_, plane_of_;
  // Planes: s_.planes is where they are now; rest_planes_ where a moving one oscillates about, plane_v_
  // their velocities now (zero for planes at rest, so the contact arithmetic is the same for both).
  std::vector<Plane3> rest_planes_;
  std::vector<Vec3> plane_v_;
  bool planes_move_ = false;
  void place_planes(double t);
  SphereCells cells_;
  PairBatch batch_;  // the sweep's scratch: a block of rows' touching pairs
  bool pending_kick_ = false, moved_ = true, sweep_allowed_ = true;
  // Whether the next drift takes some sphere half a skin from the build positions, as predicted by the
  // last force evaluation (unknown: no prediction, drift all and look; asked: this rank's answer is
  // moves_here_, the other ranks' come with the next ghost update).
  enum class Prediction { unknown, stays, moves, asked };
  Prediction prediction_ = Prediction::unknown;
  bool moves_here_ = false;
  std::size_t lag_ = 0;  // the largest j - i of a listed pair
  std::uint64_t steps_ = 0;
  // Distributed: the regions, which slots are ghosts, and the per-step ghost plan (this rank's slots
  // sent to rank to_[k]; slots filled from rank from_[k], in the order sent).
  std::optional<Domain> domain_;
  Decomposition decomposition_;
  std::vector<std::uint8_t> ghost_;
  std::vector<std::uint8_t> not_swept_;  // ghosts, and spheres sent as ghosts (drifted before the sweep)
  // The sweep's steps t in [first, last) that are a serial bed's: sphere t drifts in the sweep and the
  // row of t - lag is this rank's (set at each rebuild).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> plain_runs_;
  std::vector<int> to_, from_;
  std::vector<std::vector<std::uint32_t>> send_slots_, recv_slots_;
  // This rank's spheres sent as ghosts, each once in slot order (a sphere near both edges of a slab
  // narrower than two halos goes to two ranks, and must still drift once a step).
  std::vector<std::uint32_t> sent_once_;
  std::vector<std::vector<double>> send_buf_, recv_buf_;
  // Whether every rank sends ghosts to every other (two ranks, as a rule): then the rebuild test rides
  // on the next step's ghost update instead of taking an allreduce of its own (the same on every rank).
  bool flag_rides_ = false;
  // Balancing by measured time: this rank's load (its spheres plus their listed pairs, as the re-cut
  // counts it), each sweep's seconds per unit of that load since the last probe, the step of the next
  // probe, and whether the next step re-cuts (the same on every rank).
  double own_load_ = 0;
  std::vector<double> sweep_cost_;
  std::vector<double> asked_;  // the shares the last probe asked for (column shares, then row shares)
  std::uint64_t next_probe_ = 0;
  bool recut_now_ = false;
  std::uint64_t recuts_ = 0;
  std::uint64_t evaluations_ = 0;
  std::size_t contacts_ = 0;
};

template <class Fn>
void SphereBed::each_state(Fn&& fn) const {
  SphereState s;
  for (std::size_t k = 0; k < x_.size(); ++k) {
    if (ghost(k)) continue;
    s.id = id_[k], s.x = x_[k], s.v = v_[k], s.w = w_[k], s.f = f_[k], s.tq = tq_[k], s.q = q_[k];
    s.m = m_[k], s.inv_i = inv_i_[k], s.r = r_[k], s.material = mat_[k];
    fn(static_cast<const SphereState&>(s));
  }
}

}  // namespace grainlab::dem
