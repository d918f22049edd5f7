#pragma once
// The native 2-D discrete element engine: discs, convex polygons and walls with the thesis's
// contact law, integrated by the thesis's predictor-corrector or by velocity Verlet.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "contact_law.hpp"
#include "domain.hpp"
#include "h5_output.hpp"
#include "particles.hpp"
#include "scene.hpp"
#include "walls.hpp"
#include "wind.hpp"
#include "world_types.hpp"

namespace grainlab::dem {

struct ContactGeometry;

// How a world is spread over MPI ranks. Serial: this process holds every particle. Distributed: the
// ranks split the plane into a grid of regions (slabs along x by default), each owns the particles in
// its region and keeps copies (ghosts) of its neighbours' particles within reach; results are bitwise
// those of the serial run.

// The scene's bodies with its generated assemblies expanded (a poured bed is settled on this engine),
// at their initial state: what another engine needs to build the same scene.
std::vector<BodySpec> expanded_bodies(const Scene& scene);

// Everything a world needs to continue exactly where it was: what a checkpoint holds.
struct WorldState;

class World {
 public:
  // A committed shear-spring extension keyed by the pair's ids (b < 0: wall -1 - b), which is how
  // history survives reordering and travels with migrating particles.
  struct SavedShear {
    std::uint64_t key;
    std::int64_t a, b;
    double xi;
    bool operator<(const SavedShear& o) const { return key < o.key; }
  };
  static std::uint64_t shear_key(std::int64_t a, std::int64_t b);
  // The shear-history key of a contact with a polygon: the ids of its bodies (a wall as -1 - index) and
  // which vertex or sub-contact it is; survives reordering and migration between ranks.
  static std::uint64_t general_key(std::int64_t a, std::int64_t b, int sub);
  explicit World(const Scene& scene, Decomposition decomposition = {});

  // Advances to time `t_end` (not beyond). Throws std::runtime_error if the step underflows.
  void advance_to(double t_end);
  // One integrator step (accepted); returns the step taken.
  double step();

  double time() const { return t_; }
  // This rank's particles: the first owned_count() are its own, the rest ghosts (none when serial).
  const Particles& particles() const { return p_; }
  std::size_t owned_count() const { return n_own_; }
  bool distributed() const { return domain_.has_value(); }
  // Every particle of the world, ordered by id: on rank 0 (collective in a distributed world; the
  // other ranks get none).
  Particles gather_particles() const;
  // Where this rank's time went and what it holds (for load balance and scaling reports).
  struct RankLoad {
    double seconds_compute = 0, seconds_communication = 0;
    std::size_t owned = 0, ghosts = 0, pairs = 0, balances = 0;
  };
  const RankLoad& rank_load() const { return load_; }
  // The whole state, particles ordered by id, on rank 0 (collective; other ranks get an empty state).
  WorldState save_state() const;
  // Continues from a saved state (every rank passes the whole state; each keeps its slab). The scene
  // must be the one the state was saved from. Throws std::runtime_error if the particles do not match.
  void restore_state(const WorldState& s);
  Particles& particles() { return p_; }
  const std::vector<std::vector<Vec2>>& polygon_shapes() const { return polygons_; }
  const std::vector<Wall>& walls() const { return walls_; }
  const Effects& effects() const { return effects_; }
  const Diagnostics& diagnostics() const { return diag_; }
  const Scene& scene() const { return scene_; }
  // The wind of effect wind_drag (null without it).
  const WindField* wind() const { return wind_ ? &*wind_ : nullptr; }
  Energies energies() const;
  // Index of the particle with stable id `id`, or -1.
  long index_of(std::int64_t id) const;
  // Counts contacts at the current state (a diagnostic pass; collective in a distributed world).
  std::size_t count_contacts() const;
  // Sets the step used by Verlet (and the next predictor-corrector step).
  void set_dt(double dt) { dt_ = dt; }
  double dt() const { return dt_; }
  std::size_t history_entries() const;
  // Bytes held by particle state, neighbour lists and contact history.
  std::size_t memory_bytes() const;
  // Per-step normal impulse on each touching pair (particle ids; -1 - k for wall k): what contact events
  // are built from. Filled only while an after-step hook is set.
  const PairForces& step_impulses() const { return impulses_; }
  // Called after every accepted step with (time, step length); empty: nothing is called and the force
  // kernels record nothing (no cost to a run that does not track contacts).
  void set_after_step(std::function<void(double, double)> f) { after_step_ = std::move(f); }

 private:
  friend class ForceKernels;
  void add_bodies_from_scene();
  void add_particle(const BodySpec& b);
  void expand_assemblies();
  void setup_laws();
  void check_period(double rmax) const;
  void rebuild_neighbors();
  void rebuild_after_restore(std::vector<SavedShear> history);
  std::vector<SavedShear> save_history() const;
  void restore_history(std::vector<SavedShear>& saved);
  void sort_owned_by_cell();
  void build_pair_lists();
  void build_incidence();
  // Distributed worlds (domain.cpp).
  void distribute_initial();
  void migrate(std::vector<SavedShear>& saved);
  void receive_ghosts();
  void update_ghosts();
  void balance_regions();
  bool any_rank(bool mine) const;
  bool needs_rebuild(double lookahead) const;
  // body_forces_ready: the caller has already set forces to m g and torques to zero.
  void compute_forces(double t, double shear_h, bool body_forces_ready = false);
  void commit_history();
  void step_verlet();
  void step_predictor_corrector();
  void wrap_periodic();
  double polygon_elastic_energy() const;
  void finish_step_impulses(double taken);
  // Every contact with a polygon at the current state, with its law and its shear-history key.
  void visit_polygon_contacts(
      const std::function<void(const ContactLaw&, const ContactGeometry&, std::uint64_t)>& visit) const;

  Scene scene_;
  Effects effects_;
  Particles p_;
  std::size_t n_own_ = 0;
  Decomposition decomposition_;
  std::optional<Domain> domain_;
  bool ghosts_fresh_ = false;
  // Added to the pair and ghost reach for a list built away from its particles' build positions (after a
  // restart): they may then move a whole skin, not half, before the next rebuild.
  double extra_reach_ = 0;  // the ghosts hold their owners' current positions and velocities
  mutable RankLoad load_;   // bookkeeping, also updated by the const collectives
  std::vector<std::vector<Vec2>> polygons_;
  std::vector<Wall> walls_;
  std::vector<ContactLaw> laws_;  // [mat_a * n_mat + mat_b]
  int n_mat_ = 1;
  Vec2 g_{};  // gravity, reduced by buoyancy when that effect is on
  std::optional<WindField> wind_;
  double period_ = 0, xmin_ = 0;  // periodic in x when period_ > 0
  double t_ = 0, dt_ = 0, dt_prev_ = 0;
  bool have_prev_ = false;
  double skin_ = 0;
  Diagnostics diag_;

 public:
  // Neighbour list (half list, CSR) with its per-pair shear history; public for the kernels and tests.
  // Rows are the pairs' lower-id particles, so each pair is computed in one orientation everywhere.
  struct PairList {
    std::vector<std::uint32_t> offset, j;
    std::vector<double> shift;       // x image shift added to x_i - x_j
    std::vector<double> xi, xi_new;  // committed and trial shear-spring extension per pair
    // Per pair k, together: force on the row's particle (x, y; the partner takes its negative) and the
    // shear force, which gives each disc the torque r_i f_s.
    std::vector<double> force;
    std::vector<std::uint8_t> touching;  // pair k touched at the latest evaluation (else force is stale)
    std::vector<std::uint8_t> particle_touching;  // particle i touched something then
    // Each owned particle's pairs in ascending partner id: 2k (it is the row) or 2k + 1 (the partner).
    std::vector<std::uint32_t> inc_offset, inc;
  };
  struct WallList {
    std::vector<std::uint32_t> particle;  // discs near the wall
    std::vector<double> xi, xi_new;
  };
  struct GeneralPair {
    std::uint32_t i, j;
    double shift;
  };

 private:
  PairList discs_;
  std::vector<WallList> wall_lists_;
  std::vector<GeneralPair> general_pairs_;        // pairs with a polygon
  std::vector<std::uint32_t> polygon_particles_;  // polygons (all checked against walls)
  std::unordered_map<std::uint64_t, double> general_xi_, general_xi_new_;  // keyed by general_key
  std::vector<double> x_build_, y_build_;
  // Predictor-corrector scratch.
  std::vector<double> x0_, y0_, th0_, vx0_, vy0_, w0_, ax0_, ay0_, al0_;
  std::vector<std::uint32_t> order_;
  std::vector<Vec2> outline_a_, outline_b_;
  // Contact events: the normal force per pair at the latest evaluation and at the step's start; both
  // integrators apply the trapezoid of the two, so the step's impulse is dt (F_start + F_end) / 2.
  PairForces pair_force_, pair_force_start_, impulses_;
  std::function<void(double, double)> after_step_;
};

struct WorldState {
  Particles particles;                     // ordered by id
  std::vector<double> x_build, y_build;    // where each particle was at the last neighbour-list build
  std::vector<World::SavedShear> history;  // committed shear springs (b < 0: wall -1 - b)
  double t = 0, dt = 0, dt_prev = 0;
  bool have_prev = false;
  Diagnostics diagnostics;
  std::vector<double> wind;  // WindField::save(), empty without wind_drag
};

// A state as tables (prefix + "particles", "history", "clock") for a checkpoint file, and back.
std::vector<SampleTable> state_tables(const WorldState& s, const std::string& prefix);
std::map<std::string, std::vector<std::string>> state_table_columns(const std::string& prefix);
// Throws std::runtime_error if the tables are inconsistent.
WorldState state_from_tables(const std::map<std::string, SampleTable>& tables, const std::string& prefix);

// The clock of either engine (time, steps and step diagnostics) as one table row, and back.
struct SavedClock {
  double t = 0, dt = 0, dt_prev = 0;
  bool have_prev = false;
  Diagnostics diagnostics;
};
extern const std::vector<std::string> kClockColumns;
SampleTable clock_table(const std::string& name, const SavedClock& c);
// Throws std::runtime_error unless the table has one row.
SavedClock clock_from_table(const SampleTable& t);

}  // namespace grainlab::dem
