// Box2D 2.4.1 behind the Engine interface. Mapping decisions (docs/engines.md):
// - Units: lengths are scaled so a typical body is one Box2D unit across (Box2D is tuned for 0.1-10 m
//   bodies: linear slop 0.005), or smaller if the scene's speeds would exceed Box2D's maximum
//   translation per step (2 units), which clamps velocities; time and mass are unchanged.
// - Materials: every contact gets the scene's pair restitution and friction in PreSolve, overriding
//   Box2D's mixing rules; the restitution threshold is 0 (Box2D's default 1 m/s would make slow
//   impacts perfectly inelastic); sleeping is off.
// - Soft-contact materials (k_n with damping) become the restitution eq. 2.2 gives for the contact's
//   reduced mass: Box2D's contacts are rigid, so stiffness itself is not modelled.
#include <box2d/box2d.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "engine.hpp"

namespace grainlab {

namespace {

struct BodyInfo {
  std::int64_t id = -1;  // -1: wall
  int material = 0;
  double mass = 0;  // 0: infinite (wall)
  int shape = -1;   // polygon index, -1 disc or wall
  double radius = 0;
  std::size_t wall = 0;
};

class PairMaterials : public b2ContactListener {
 public:
  PairMaterials(const Scene& scene) : scene_(scene) {}
  void PreSolve(b2Contact* contact, const b2Manifold*) override {
    const auto* a = reinterpret_cast<const BodyInfo*>(contact->GetFixtureA()->GetUserData().pointer);
    const auto* b = reinterpret_cast<const BodyInfo*>(contact->GetFixtureB()->GetUserData().pointer);
    const Material& m = scene_.pair(a->material, b->material);
    const double meff = a->mass == 0   ? b->mass
                        : b->mass == 0 ? a->mass
                                       : a->mass * b->mass / (a->mass + b->mass);
    contact->SetRestitution(static_cast<float>(impulse_engine_restitution(m, meff)));
    contact->SetFriction(scene_.effects.has(Effect::friction) ? static_cast<float>(m.mu) : 0.0f);
    contact->SetRestitutionThreshold(0.0f);
  }
  // Normal impulses per touching pair, summed over a step's solver passes (Box2D units), when asked for.
  void PostSolve(b2Contact* contact, const b2ContactImpulse* impulse) override {
    if (!impulses) return;
    const auto* a = reinterpret_cast<const BodyInfo*>(contact->GetFixtureA()->GetUserData().pointer);
    const auto* b = reinterpret_cast<const BodyInfo*>(contact->GetFixtureB()->GetUserData().pointer);
    double sum = 0;
    for (int k = 0; k < impulse->count; ++k) sum += impulse->normalImpulses[k];
    (*impulses)[{id(a), id(b)}] += sum;
  }
  PairImpulses* impulses = nullptr;

 private:
  static std::int64_t id(const BodyInfo* i) {
    return i->id >= 0 ? i->id : -1 - static_cast<std::int64_t>(i->wall);
  }
  const Scene& scene_;
};

class Box2DEngine final : public Engine {
 public:
  Box2DEngine(const Scene& scene, std::vector<BodySpec> bodies)
      : scene_(scene), bodies_(std::move(bodies)), world_(b2Vec2(0, 0)), materials_(scene_) {
    scale_ = length_scale();
    bullets_ = tunnelling_possible();
    if (scene_.effects.has(Effect::gravity)) world_.SetGravity(vec(scene_.gravity));
    world_.SetAllowSleeping(false);
    world_.SetContactListener(&materials_);
    info_.reserve(bodies_.size() + scene_.walls.size());
    for (const BodySpec& b : bodies_) add_body(b);
    for (std::size_t w = 0; w < scene_.walls.size(); ++w) add_wall(w);
  }

  std::string name() const override { return "box2d"; }
  std::string integrator() const override { return "box2d sequential impulses (semi-implicit Euler)"; }
  double time() const override { return t_; }

  void advance_to(double t_end) override {
    const auto start = std::chrono::steady_clock::now();
    const Accuracy& a = scene_.accuracy;
    const double h = a.dt / a.substeps;
    while (t_ + h * (1 - 1e-3) <= t_end) {
      move_walls(h);
      PairImpulses step;
      materials_.impulses = tracking_contacts() ? &step : nullptr;
      world_.Step(static_cast<float>(h), a.velocity_iterations, a.position_iterations);
      t_ += h;
      ++steps_;
      if (tracking_contacts()) {
        for (auto& [pair, j] : step) j /= scale_;  // g x units/s -> g cm/s
        record_contacts(t_, h, step);
      }
      max_contacts_ = std::max<double>(max_contacts_, world_.GetContactCount());
    }
    wall_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  Frame frame() const override {
    Frame f;
    f.time = t_;
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const b2Body* b = handles_[k];
      const b2Vec2 p = b->GetPosition(), v = b->GetLinearVelocity();
      f.add_body(bodies_[k].id, p.x / scale_, p.y / scale_, v.x / scale_, v.y / scale_, b->GetAngle(),
                 b->GetAngularVelocity(), bodies_[k].radius, info_[k].shape);
    }
    return f;
  }

  EnergyReport energies() const override { return rigid_body_energies(frame(), bodies_, scene_); }

  std::map<std::string, double> diagnostics() const override {
    return {{"steps", double(steps_)},
            {"rejected_steps", 0.0},
            {"force_evaluations", double(steps_)},
            {"solver_velocity_iterations", double(scene_.accuracy.velocity_iterations)},
            {"solver_position_iterations", double(scene_.accuracy.position_iterations)},
            {"contacts", double(world_.GetContactCount())},
            {"max_contacts", max_contacts_},
            {"wall_seconds", wall_seconds_},
            {"length_scale_units_per_cm", scale_},
            // Edges and polygons are b2_polygonRadius thick: bodies touch this much early.
            {"edge_skin_cm", b2_polygonRadius / scale_},
            {"particles", double(bodies_.size())}};
  }

  std::vector<std::vector<double>> polygon_shapes() const override { return polygon_outlines(bodies_); }

 private:
  // Box2D units per cm: a median body diameter becomes one unit, unless the fastest motion the scene
  // can reach (initial speeds plus g x duration) would then exceed Box2D's cap of b2_maxTranslation
  // per step, which silently clamps velocities; then lengths are scaled down until it fits (with a
  // factor 2 margin for impacts).
  double length_scale() const {
    double scale = unit_per_median_diameter(bodies_);
    const double vmax = speed_bound(), step = scene_.accuracy.dt / scene_.accuracy.substeps;
    if (vmax > 0) scale = std::min(scale, 0.5 * b2_maxTranslation / (vmax * step));
    return scale;
  }
  // The fastest any point of a body can move in this scene: the largest initial speed (rim included)
  // plus what gravity adds over the duration. Contacts only share that energy out.
  double speed_bound() const {
    double vmax = 0;
    for (const BodySpec& b : bodies_) vmax = std::max(vmax, norm(b.velocity) + std::abs(b.spin) * b.radius);
    if (scene_.effects.has(Effect::gravity)) vmax += norm(scene_.gravity) * scene_.duration;
    return vmax;
  }
  // Continuous collision (Box2D "bullets") where a step could carry a body a quarter of the smallest
  // radius: then a fast grain must not tunnel through a thin bed. Elsewhere it only costs time: with
  // every body a bullet, b2World::SolveTOI took most of a step in the 300-disc poured bed (4.8 s for
  // 500 steps, against 0.2 s without; there no step can carry a body more than 0.016 cm, 4 % of the
  // smallest radius).
  bool tunnelling_possible() const {
    double rmin = std::numeric_limits<double>::max();
    for (const BodySpec& b : bodies_) rmin = std::min(rmin, b.radius);
    return speed_bound() * scene_.accuracy.dt / scene_.accuracy.substeps > 0.25 * rmin;
  }
  b2Vec2 vec(Vec2 v) const {
    return b2Vec2(static_cast<float>(v.x * scale_), static_cast<float>(v.y * scale_));
  }

  void add_body(const BodySpec& s) {
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position = vec(s.position);
    def.angle = static_cast<float>(s.angle);
    def.linearVelocity = vec(s.velocity);
    def.angularVelocity = static_cast<float>(scene_.effects.has(Effect::rotation) ? s.spin : 0.0);
    def.fixedRotation = !scene_.effects.has(Effect::rotation);
    def.bullet = bullets_;
    def.allowSleep = false;
    b2Body* body = world_.CreateBody(&def);
    BodyInfo info{s.id, s.material, s.mass, -1, s.radius, 0};
    b2FixtureDef fd;
    fd.density = 1.0f;  // replaced by SetMassData below
    fd.restitutionThreshold = 0.0f;
    fd.isSensor = !scene_.effects.has(Effect::normal_contact);
    b2CircleShape circle;
    b2PolygonShape poly;
    if (s.shape == BodySpec::Shape::Disc) {
      circle.m_radius = static_cast<float>(s.radius * scale_);
      fd.shape = &circle;
    } else {
      std::vector<b2Vec2> v;
      for (Vec2 p : s.vertices) v.push_back(vec(p));
      poly.Set(v.data(), static_cast<int>(v.size()));
      fd.shape = &poly;
      info.shape = polygons_++;
    }
    info_.push_back(info);
    fd.userData.pointer = reinterpret_cast<uintptr_t>(&info_.back());
    body->CreateFixture(&fd);
    b2MassData md;
    md.mass = static_cast<float>(s.mass);
    md.center = b2Vec2(0, 0);
    md.I = static_cast<float>(s.inertia * scale_ * scale_);
    body->SetMassData(&md);
    handles_.push_back(body);
  }

  void add_wall(std::size_t w) {
    const WallSpec& s = scene_.walls[w];
    b2BodyDef def;
    def.type = s.motion.active() ? b2_kinematicBody : b2_staticBody;
    b2Body* body = world_.CreateBody(&def);
    b2EdgeShape edge;
    if (s.kind == WallSpec::Kind::Segment) {
      edge.SetTwoSided(vec(s.a), vec(s.b));
    } else {  // an infinite line as a long edge, 1e4 body sizes each way
      const Vec2 t{-s.b.y, s.b.x};
      const double half = 1e4 / scale_;
      edge.SetTwoSided(vec(s.a - t * half), vec(s.a + t * half));
    }
    info_.push_back({-1, s.material, 0.0, -1, 0.0, w});
    b2FixtureDef fd;
    fd.shape = &edge;
    fd.restitutionThreshold = 0.0f;
    fd.userData.pointer = reinterpret_cast<uintptr_t>(&info_.back());
    body->CreateFixture(&fd);
    walls_.push_back(body);
  }

  // Kinematic walls move at the mean velocity of the step, so they land exactly on the prescribed path.
  void move_walls(double h) {
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      const Motion& m = scene_.walls[w].motion;
      if (!m.active()) continue;
      const Vec2 v = (wall_offset(m, t_ + h) - wall_offset(m, t_)) * (1 / h);
      walls_[w]->SetLinearVelocity(vec(v));
    }
  }

  Scene scene_;
  std::vector<BodySpec> bodies_;
  bool bullets_ = true;
  b2World world_;
  PairMaterials materials_;
  std::vector<BodyInfo> info_;  // reserved up front: fixtures point into it
  std::vector<b2Body*> handles_, walls_;
  double scale_ = 1, t_ = 0, wall_seconds_ = 0, max_contacts_ = 0;
  std::uint64_t steps_ = 0;
  int polygons_ = 0;
};

}  // namespace

std::unique_ptr<Engine> make_box2d_engine(const Scene& scene, std::vector<BodySpec> bodies) {
  return std::make_unique<Box2DEngine>(scene, std::move(bodies));
}

}  // namespace grainlab
