#pragma once
// The native engine in 3-D: spheres and convex polyhedra (with any centre of mass and full inertia
// tensor) on planes, the thesis's contact law at every contact point with the tangential spring kept in
// the tangent plane, quaternion orientations, and the same two integrators as in 2-D (the thesis's
// adaptive predictor-corrector, eq. 2.4, and velocity Verlet). The broad phase is all pairs by
// bounding sphere: this engine is meant for the few-body problems of Ch. II (die, block, impacts).
#include <cstdint>
#include <functional>
#include <map>
#include <tuple>
#include <vector>

#include "contact_law.hpp"
#include "h5_output.hpp"
#include "narrow_phase3d.hpp"
#include "scene.hpp"
#include "sphere_bed.hpp"
#include "sphere_cells.hpp"
#include "world_types.hpp"

namespace grainlab::dem {

struct Body3 {
  std::int64_t id = 0;
  Vec3 x = Vec3::Zero(), v = Vec3::Zero(), w = Vec3::Zero();  // w: angular velocity, world frame
  Quat q = Quat::Identity();
  double m = 0, inv_m = 0;
  Mat3 inertia = Mat3::Identity(), inv_inertia = Mat3::Identity();  // body frame, about the centre of mass
  const Polyhedron* hull = nullptr;
  double radius = 0;
  int material = 0;
  bool isotropic = false;  // inertia the same about every axis (spheres, cubes): no rotation needed
  bool held = false;       // held in place (Body3Spec::held): inv_m and the inverse inertia are zero
  Vec3 f = Vec3::Zero(), tq = Vec3::Zero();  // force and torque of the last evaluation (world)
  Mat3 world_inv_inertia() const;
  Vec3 angular_momentum() const;
};

// A contact's shear-spring state, keyed by (body id A, body id B or -1 - plane index, feature).
using ContactKey3 = std::tuple<std::int64_t, std::int64_t, int>;

// The scene's 3-D bodies followed by its generated assemblies (lattices; pours settled on this engine),
// at their initial state: what World3d and the other 3-D engines build the scene from.
std::vector<Body3Spec> expanded_bodies3d(const Scene& scene);
// A scene of one poured assembly (and no other bodies) as the run it takes: the settling scene with the
// grains dropped at rest where expanded_bodies3d drops them, to be advanced for the assembly's settle_time
// (and the velocity it gives set) to give expanded_bodies3d's bodies, bit for bit. So a caller can run,
// and checkpoint, a long pour itself.
Scene pour_settling_scene(const Scene& scene);

class World3d {
 public:
  // A decomposition spreads a bed of spheres over the MPI ranks (sphere_bed_parallel.cpp): then bodies()
  // is current on rank 0 for all bodies (gathered after each advance) and on the others for their own,
  // and energies(), save_state() and contact counts are collective.
  explicit World3d(const Scene& scene, Decomposition decomposition = {});
  // Neighbour lists (and the sphere kernel, on one rank) from this many bodies on (see bin_bodies).
  static constexpr std::size_t kCellsFrom = 32;
  bool distributed() const { return decomposition_.distributed; }
  void advance_to(double t_end);
  double time() const { return t_; }
  const std::vector<Body3>& bodies() const { return b_; }
  const Scene& scene() const { return scene_; }
  const Diagnostics& diagnostics() const { return diag_; }
  Energies energies() const;
  // Contacts at the last evaluation (on every rank of a distributed world: collective).
  std::size_t count_contacts() const;
  // Per-step normal impulse on each touching pair (body ids; -1 - k for plane k): what contact events
  // are built from.
  const PairForces& step_impulses() const { return impulses_; }
  // Called after every accepted step with (time, step length); empty: nothing is called.
  void set_after_step(std::function<void(double, double)> f) { after_step_ = std::move(f); }
  // Beds of spheres (at least kCellsFrom of them, velocity Verlet, no after-step callback) run on the
  // sphere kernel: the same physics on arrays of the hot fields, with the shear springs kept beside the
  // neighbour lists instead of in a map. false (before the first advance): the general path, for tests.
  void use_sphere_kernel(bool on) { sphere_kernel_allowed_ = on; }
  bool on_sphere_kernel() const { return mode_ == Mode::spheres; }
  // Threads for the general path's narrow phase and integration (before the first advance; default:
  // narrow_phase_threads() in world3d.cpp). Any number gives the same bits.
  void use_threads(int n) { threads_ = std::max(1, n); }
  // Tests: false makes the sphere kernel take two passes every step instead of one sweep.
  void allow_sweep(bool on) { bed_.allow_sweep(on); }

  // Checkpoints (velocity Verlet): the whole state as tables under `prefix` (bodies, springs, clock),
  // and back. A restored world continues bit for bit: the sphere kernel's lists are rebuilt at the saved
  // build positions, so its rebuilds, periodic wrapping and spring slots come back as they were.
  bool checkpointable() const { return scene_.accuracy.integrator == Integrator::VelocityVerlet; }
  std::vector<SampleTable> save_state(const std::string& prefix) const;
  static std::map<std::string, std::vector<std::string>> state_columns(const std::string& prefix);
  // Throws std::runtime_error if the tables do not fit this scene.
  void restore_state(const std::map<std::string, SampleTable>& tables, const std::string& prefix);

 private:
  // Sphere kernel or general path, once, before the first step (or at a restore).
  void decide_mode();
  void check_decomposition() const;
  void step();
  void step_verlet();
  void step_predictor_corrector();
  // Forces and torques at the current state; `h` is the time since the committed shear-spring state.
  // Forces at time t (moving planes are placed there first); h: the shear spring's step.
  void compute_forces(double t, double h);
  void place_planes(double t);
  static std::vector<Placed3> unplaced(const std::vector<Body3>& bodies);
  // Rebuilds the broad phase's Verlet lists when a body has moved half the skin (skin_fraction of the
  // largest bounding radius) since the last build. From kCellsFrom bodies on; fewer are paired all with
  // all, which visits the same pairs in the same order.
  void bin_bodies(SphereCells& cells, std::vector<Vec3>& centres, double skin_fraction) const;
  // After the lists are rebuilt, moves each pair's separating axis and Gauss-map crossings to the pair's
  // place in the new lists (pairs new to them start without).
  void carry_pair_memory();
  // Places every body and finds the contacts of every listed pair, in parallel (OpenMP), each thread over
  // its own run of bodies (part) into its own buffer, in list order; the per-entry counts say which
  // contacts are whose, so the forces are then summed in one thread in exactly the serial order.
  void place_bodies(bool first_placement);
  void find_listed_contacts();
  void cut_parts(int parts);
  // Below this many bodies a step is too short to share between threads.
  static constexpr std::size_t kThreadsFrom = 256;
  bool threaded() const { return threads_ > 1 && b_.size() >= kThreadsFrom; }
  void add_contact(Body3& a, Body3* b, const ContactPoint3& c, const ContactLaw& law, std::int64_t key_b,
                   double h);
  Vec3 angular_acceleration(const Body3& b) const;
  void commit_history() {
    trial_.sort();
    history_.swap(trial_);
  }
  // The sphere kernel (sphere_bed.*): loaded at the first advance, mirrored into b_ after each.
  bool sphere_kernel_eligible() const;
  void load_bed(bool spread = true);  // spread: over the ranks, when distributed
  void check_periods(double r_max) const;
  void store_bed();
  SphereBedSetup bed_setup() const;
  Energies bed_energies(const Vec3& g) const;
  std::size_t body_of_id(std::int64_t id) const;
  // Rank 0 gets every sphere's build position (by body index) and every spring held, sorted.
  void gather_bed_state(std::vector<Vec3>& built, std::vector<SphereSpring>& springs) const;
  enum class Mode { undecided, general, spheres };
  Mode mode_ = Mode::undecided;
  bool sphere_kernel_allowed_ = true, bed_loaded_ = false;
  SphereBed bed_;
  std::vector<std::size_t> bed_body_;  // the body index of each of this rank's spheres, in the bed's order
  std::vector<std::pair<std::int64_t, std::size_t>> by_id_;  // (id, body index), sorted

  Scene scene_;
  Effects effects_;
  Decomposition decomposition_;
  std::vector<Body3> b_;
  std::vector<Placed3> placed_;  // the general path's, built at its first force evaluation (unplaced())
  std::vector<Plane3> planes_;   // where they are at the last force evaluation
  std::vector<Vec3> plane_v_;    // their velocities then (zero for planes at rest)
  std::vector<int> plane_material_;
  std::vector<ContactLaw> laws_;
  int n_mat_ = 1;
  struct Spring {
    Vec3 xi = Vec3::Zero();
    double k_s = 0;
  };
  // The general path's shear springs by contact key, in key order as a std::map keeps them, but in one
  // array: a step appends its contacts' springs (nearly in order already) and sorts them once, instead of
  // allocating a tree node per contact per step.
  class SpringBook {
   public:
    using Entry = std::pair<ContactKey3, Spring>;
    const Spring* find(const ContactKey3& key) const;
    void append(const ContactKey3& key, const Spring& s) { entries_.push_back({key, s}); }
    // Into key order, the last of equal keys kept (what assigning into a map would leave).
    void sort();
    void clear() { entries_.clear(); }
    void swap(SpringBook& o) { entries_.swap(o.entries_); }
    std::vector<Entry>::const_iterator begin() const { return entries_.begin(); }
    std::vector<Entry>::const_iterator end() const { return entries_.end(); }

   private:
    std::vector<Entry> entries_;
  };
  SpringBook history_, trial_;
  std::vector<ContactPoint3> scratch_;
  SphereCells cells_;
  std::vector<Vec3> centres_;  // bin_bodies' scratch, kept so no step allocates
  // Per entry of cells_'s lists, the axis that last separated the pair (hull_hull), and the build of the
  // lists they belong to.
  std::vector<SeparatingHint> separating_;
  std::vector<GaussCrossings> crossings_;  // per entry too: a touching pair's Gauss-map crossings
  std::size_t separating_build_ = 0;
  // The lists separating_ and crossings_ are laid out by (cells_'s offsets and partners at that build).
  std::vector<SphereCells::Index> memory_offsets_, memory_partners_;
  std::vector<std::vector<ContactPoint3>> part_contacts_;  // find_listed_contacts' output, per part
  std::vector<std::size_t> part_start_;                    // the parts' first bodies, and n
  std::vector<std::uint32_t> touching_;                    // each body's touching pairs at the last sum
  std::vector<std::uint16_t> plane_contacts_;  // and each body's with each plane (after its pairs')
  std::vector<std::uint16_t> entry_contacts_;  // and how many of them each list entry has
  int threads_ = 1;                            // narrow_phase_threads(), at construction
  PairForces impulses_, step_force_, end_force_;
  double t_ = 0, dt_ = 0, dt_prev_ = 0;
  bool have_prev_ = false;
  std::vector<Body3> start_;  // state at the start of a predictor-corrector step
  std::vector<Vec3> a0_, al0_, v_prev_, w_prev_;
  std::size_t last_contacts_ = 0, contacts_now_ = 0;
  Diagnostics diag_;
  std::function<void(double, double)> after_step_;
};

}  // namespace grainlab::dem
