#pragma once
// One interface over the engines: native (2-D and 3-D), Box2D (2-D), Bullet and ODE (3-D, and 2-D by
// constraining motion to the plane). Engines work in cgs; results leave through in_scene_units().
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "contact_events.hpp"
#include "h5_output.hpp"
#include "scene.hpp"

namespace grainlab {

struct EnergyReport {
  double kinetic_translational = 0, kinetic_rotational = 0, potential_gravity = 0, elastic = 0;
  double total() const { return kinetic_translational + kinetic_rotational + potential_gravity + elastic; }
};

// What an engine can simulate. A scene asking for more stops with a message naming the engine and the
// missing capability; nothing is silently approximated.
class Engine;
struct Capabilities {
  std::string name, description;
  std::vector<int> dimensions;  // 2 and/or 3
  std::vector<std::string>
      shapes;  // 2-D: disc, polygon, segment, line, moving wall; 3-D: sphere, polyhedron, plane, moving plane
  std::vector<std::string> effects;  // effect names from scene.hpp
  bool periodic = false;
  bool generated_assemblies = false;
  int max_polygon_vertices = 0;  // 0: no limit
  std::string contact_model;
  std::string contact_events;  // which dimensions report contact events, and how they are measured
  // Contacts are soft springs whose duration the step must resolve (the native engine), rather than
  // rigid impulses: validation picks steps and checks by this, never by the engine's name.
  bool soft_contacts = false;
  std::function<std::unique_ptr<Engine>(const Scene&)> make;
  bool distributed = false;  // 2-D disc scenes can be spread over MPI ranks
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual std::string name() const = 0;
  virtual void advance_to(double t) = 0;
  virtual double time() const = 0;
  virtual Frame frame() const = 0;  // particles ordered by id
  virtual EnergyReport energies() const = 0;
  virtual std::map<std::string, double> diagnostics() const = 0;
  virtual std::vector<std::vector<double>> polygon_shapes() const = 0;  // flat x,y per polygon
  virtual std::string integrator() const = 0;

  // Checkpoints (the native engine: 2-D discs, 3-D under Verlet): the whole state as tables, and back.
  // save_state is collective in a distributed engine (rank 0 gets the tables); restore_state is given the
  // whole state on every rank and throws std::runtime_error if it does not fit the scene.
  virtual bool checkpointable() const { return false; }
  virtual std::vector<SampleTable> save_state() const { return {}; }
  virtual std::map<std::string, std::vector<std::string>> state_columns() const { return {}; }
  virtual void restore_state(const std::map<std::string, SampleTable>& /*tables*/) {}
  // How many MPI ranks share this engine's scene (1 unless distributed).
  virtual int ranks() const { return 1; }

  // Contact events (contact_events.hpp) are recorded from the next step on once asked for; they cost a
  // walk over the contacts each step, so they are off by default.
  void track_contacts(bool on) { tracking_ = on; }
  bool tracking_contacts() const { return tracking_; }
  std::vector<ContactEvent> contact_events() const { return tracker_.events(); }

 protected:
  // Engines call this after every step when tracking_contacts().
  void record_contacts(double t, double dt, const PairImpulses& step) { tracker_.record(t, dt, step); }

 private:
  bool tracking_ = false;
  ContactTracker tracker_;
};

const std::vector<Capabilities>& engine_catalog();
// The catalogue row of an engine; throws InputError naming the engines if it is unknown.
const Capabilities& engine_capabilities(const std::string& name);
// The restitution an impulse engine gets for a material at reduced mass m_eff: the given one, or what
// eq. 2.2 gives for a soft material's stiffness and damping.
double impulse_engine_restitution(const Material& m, double meff);
// Displacement of a prescribed-motion wall from its rest position at time t (scene units).
Vec2 wall_offset(const Motion& m, double t);
// Engine length units per cm that make the median body diameter one unit (1 when there are no bodies).
double unit_per_median_diameter(const std::vector<BodySpec>& bodies);
// Body-frame outlines of the polygon bodies, flattened x, y (for the output's /shapes).
std::vector<std::vector<double>> polygon_outlines(const std::vector<BodySpec>& bodies);
// Centre-of-mass-frame vertices of the polyhedral 3-D bodies, flattened x, y, z.
std::vector<std::vector<double>> polyhedron_vertices(const std::vector<Body3Spec>& bodies);
// Appends a 3-D body to a frame from an engine's state in cgs (position, velocity, orientation body to
// world, angular velocity in the world frame).
void append_body3d(Frame& f, const Body3Spec& b, std::int32_t shape_index, const Vec3& x, const Vec3& v,
                   const Quat& q, const Vec3& w);
// Index of each 3-D body's polyhedron in polyhedron_vertices(), -1 for spheres.
std::vector<std::int32_t> polyhedron_indices(const std::vector<Body3Spec>& bodies);
// Engine length units per cm making the median 3-D body diameter one unit.
double unit_per_median_diameter(const std::vector<Body3Spec>& bodies);
// Kinetic and gravitational energy of rigid bodies (in the frame's order) from a frame in scene units.
EnergyReport rigid_body_energies(const Frame& f, const std::vector<BodySpec>& bodies, const Scene& scene);
EnergyReport rigid_body_energies(const Frame& f, const std::vector<Body3Spec>& bodies, const Scene& scene);
// Throws InputError naming the engine and what the scene needs that it lacks.
void check_engine_supports(const Capabilities& c, const Scene& scene);

// Throws InputError if the engine is unknown.
std::unique_ptr<Engine> make_engine(const std::string& name, const Scene& scene);
// Why this run cannot be spread over MPI ranks (empty if it can): only the native engine's 2-D disc
// scenes without contact events are distributed so far.
std::string why_not_distributed(const std::string& engine, const Scene& scene);
// The native 2-D engine spread over all MPI ranks in a grid of `ranks_y` rows (1: slabs along x),
// regions re-split every `balance_every` steps (0: never).
std::unique_ptr<Engine> make_distributed_native_engine(const Scene& scene, std::uint64_t balance_every,
                                                       int ranks_y = 1);
std::vector<std::string> engine_names();
// The engines that can run scenes of this dimension (2 or 3), in catalog order.
std::vector<std::string> engines_for_dimension(int dimension);

struct RunOptions {
  std::string out;
  bool overwrite = false;
  // Called with (simulated time, duration) after every frame and regularly in between.
  std::function<void(double, double)> progress;
  // This process writes the files (rank 0 of a distributed run; the others compute only).
  bool write = true;
  // Checkpoints: written to `checkpoint` after every `checkpoint_every`-th frame (0: never).
  int checkpoint_every = 0;
  std::string checkpoint = {};
  // Stop after this frame's checkpoint, without writing the run file (0: run to the end).
  int stop_after_frame = 0;
  // Continue from this checkpoint file (empty: start from the scene).
  std::string restart = {};
};

struct RunSummary {
  std::string h5, xmf;
  bool stopped = false;  // stopped at options.stop_after_frame: only the checkpoint was written
  int restarted_from_frame = 0;
  std::map<std::string, double> diagnostics;
  EnergyReport initial, final;
};

// Engines work in cgs; results are reported in the units the scene file was written in.
Frame in_scene_units(Frame f, const Scene& scene);
EnergyReport in_scene_units(EnergyReport e, const Scene& scene);
ContactEventTable in_scene_units(const std::vector<ContactEvent>& events, const Scene& scene);
std::string units_description(const Scene& scene);

// Runs a scene to its duration, writing frames, energies, diagnostics and metadata (in the scene's units).
RunSummary run_scene(const Scene& scene, Engine& engine, const RunOptions& options);

}  // namespace grainlab
