#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "engine.hpp"
#include "parallel.hpp"
#include "world.hpp"
#include "world3d.hpp"

namespace grainlab {

namespace {

EnergyReport to_report(const dem::Energies& e) {
  return {e.kinetic_translational, e.kinetic_rotational, e.potential_gravity, e.elastic};
}

std::map<std::string, double> to_map(const dem::Diagnostics& d, std::size_t contacts, std::size_t bodies) {
  return {{"steps", double(d.steps)},
          {"rejected_steps", double(d.rejected_steps)},
          {"force_evaluations", double(d.force_evaluations)},
          {"region_recuts", double(d.region_recuts)},
          {"contacts", double(contacts)},
          {"wall_seconds", d.wall_seconds},
          {"dt_min_used", d.dt_min_used},
          {"dt_max_used", d.dt_max_used},
          {"particles", double(bodies)}};
}

// The worlds call back after every step while the engine tracks contacts (and cost nothing otherwise).
template <class World, class Record>
void hook_contact_events(World& world, bool tracking, Record record) {
  if (tracking)
    world.set_after_step([&world, record](double now, double dt) { record(now, dt, world.step_impulses()); });
  else
    world.set_after_step(nullptr);
}

// What the 2-D and 3-D native engines share: their world, stepping with contact events, time, integrator.
template <class World>
class NativeEngineBase : public Engine {
 public:
  template <class... Options>
  explicit NativeEngineBase(const Scene& scene, Options... options) : world_(scene, options...) {}
  std::string name() const override { return "native"; }
  void advance_to(double t) override {
    hook_contact_events(world_, tracking_contacts(), [this](double now, double dt, const PairImpulses& s) {
      record_contacts(now, dt, s);
    });
    world_.advance_to(t);
  }
  double time() const override { return world_.time(); }
  std::string integrator() const override {
    return world_.scene().accuracy.integrator == Integrator::VelocityVerlet ? "verlet"
                                                                            : "predictor-corrector";
  }

 protected:
  World world_;
};

class NativeEngine final : public NativeEngineBase<dem::World> {
 public:
  explicit NativeEngine(const Scene& scene, dem::Decomposition d = {}) : NativeEngineBase(scene, d) {}

  // Gathered to rank 0 in a distributed world (the other ranks return an empty frame).
  Frame frame() const override {
    const dem::Particles p = world_.gather_particles();
    Frame f;
    f.time = world_.time();
    for (std::size_t i = 0; i < p.size(); ++i)
      f.add_body(p.id[i], p.x[i], p.y[i], p.vx[i], p.vy[i], p.th[i], p.w[i], p.r[i], p.shape[i]);
    return f;
  }

  EnergyReport energies() const override { return to_report(world_.energies()); }

  std::map<std::string, double> diagnostics() const override {
    std::vector<std::uint64_t> owned{world_.owned_count()};
    if (world_.distributed()) parallel::sum_all(owned);
    auto d = to_map(world_.diagnostics(), world_.count_contacts(), owned[0]);
    d["neighbor_rebuilds"] = double(world_.diagnostics().neighbor_rebuilds);
    if (const dem::WindField* w = world_.wind()) {
      const auto& s = w->snapshot();
      d["wind_u_star_eff"] = s.u_star_eff;
      d["wind_bed_level"] = s.bed_level;
      d["wind_grain_drag_per_area"] = s.drag_per_area;
      d["wind_updates"] = s.updates;
    }
    return d;
  }

  std::vector<std::vector<double>> polygon_shapes() const override {
    std::vector<std::vector<double>> out;
    for (const auto& poly : world_.polygon_shapes()) {
      std::vector<double> flat;
      for (Vec2 v : poly) flat.insert(flat.end(), {v.x, v.y});
      out.push_back(flat);
    }
    return out;
  }

  // Polygon contacts keep their shear history in a map the state does not carry yet.
  bool checkpointable() const override { return world_.polygon_shapes().empty(); }
  std::vector<SampleTable> save_state() const override {
    return dem::state_tables(world_.save_state(), "state/");
  }
  std::map<std::string, std::vector<std::string>> state_columns() const override {
    return dem::state_table_columns("state/");
  }
  void restore_state(const std::map<std::string, SampleTable>& tables) override {
    world_.restore_state(dem::state_from_tables(tables, "state/"));
  }
  int ranks() const override { return world_.distributed() ? parallel::size() : 1; }
};

// The native engine on a 3-D scene.
class NativeEngine3d final : public NativeEngineBase<dem::World3d> {
 public:
  explicit NativeEngine3d(const Scene& scene, dem::Decomposition d = {})
      : NativeEngineBase(scene, d), shape_index_(polyhedron_indices(world_.scene().bodies3d)) {}

  // A distributed world's bodies are gathered to rank 0 after every advance; the others return an empty
  // frame.
  Frame frame() const override {
    Frame f;
    f.time = world_.time();
    if (world_.distributed() && parallel::rank() != 0) return f;
    return frame_of_all(f);
  }

  Frame frame_of_all(Frame& f) const {
    const auto& bodies = world_.bodies();
    std::vector<std::size_t> order(bodies.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return bodies[a].id < bodies[b].id; });
    for (std::size_t i : order) {
      const dem::Body3& b = bodies[i];
      append_body3d(f, world_.scene().bodies3d[i], shape_index_[i], b.x, b.v, b.q, b.w);
    }
    return f;
  }

  EnergyReport energies() const override { return to_report(world_.energies()); }

  // Collective in a distributed world (the contact count is summed over the ranks).
  std::map<std::string, double> diagnostics() const override {
    return to_map(world_.diagnostics(), world_.count_contacts(), world_.bodies().size());
  }
  int ranks() const override { return world_.distributed() ? parallel::size() : 1; }

  std::vector<std::vector<double>> polygon_shapes() const override {
    return polyhedron_vertices(world_.scene().bodies3d);
  }

  bool checkpointable() const override { return world_.checkpointable(); }
  std::vector<SampleTable> save_state() const override { return world_.save_state("state3d/"); }
  std::map<std::string, std::vector<std::string>> state_columns() const override {
    return dem::World3d::state_columns("state3d/");
  }
  void restore_state(const std::map<std::string, SampleTable>& tables) override {
    world_.restore_state(tables, "state3d/");
  }

 private:
  std::vector<std::int32_t> shape_index_;
};

}  // namespace

std::string why_not_distributed(const std::string& engine, const Scene& scene) {
  if (!engine_capabilities(engine).distributed)
    return fmt::format("the {} engine runs on one process", engine);
  if (scene.dimension == 3) {
    if (scene.accuracy.integrator != Integrator::VelocityVerlet)
      return "3-D scenes run over MPI ranks under integrator \"verlet\" only";
    for (const Body3Spec& b : scene.bodies3d)
      if (b.shape != Body3Spec::Shape::Sphere) return "3-D scenes with polyhedra run on one process so far";
    if (scene.output.contacts) return "contact events ([output] contacts) are recorded on one process so far";
    return {};
  }
  for (const BodySpec& b : scene.bodies)
    if (b.shape == BodySpec::Shape::Polygon) return "scenes with polygons run on one process so far";
  if (scene.output.contacts) return "contact events ([output] contacts) are recorded on one process so far";
  return {};
}

std::unique_ptr<Engine> make_distributed_native_engine(const Scene& scene, std::uint64_t balance_every,
                                                       int ranks_y) {
  if (scene.dimension == 3)
    return std::make_unique<NativeEngine3d>(scene, dem::Decomposition{true, balance_every, ranks_y});
  return std::make_unique<NativeEngine>(scene, dem::Decomposition{true, balance_every, ranks_y});
}

std::unique_ptr<Engine> make_native_engine(const Scene& scene) {
  if (scene.dimension == 3) return std::make_unique<NativeEngine3d>(scene);
  return std::make_unique<NativeEngine>(scene);
}

}  // namespace grainlab
