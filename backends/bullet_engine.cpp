// Bullet 3.24 (float64 libraries) behind the Engine interface. Mapping decisions (docs/engines.md):
// - 2-D scenes: bodies move in the z = 0 plane (linear factor (1, 1, 0), angular factor (0, 0, 1));
//   discs are spheres. btRigidBody (maximal coordinates), not btMultiBody.
// - Walls: a line is a static plane; a segment is a thin static box.
// - Materials: each contact gets the scene's pair restitution and friction in the contact-added
//   callback (overriding Bullet's product mixing); the restitution velocity threshold is 0 (Bullet's
//   0.2 would make slow impacts inelastic); deactivation (sleeping) is off.
// - Units: lengths scaled so a median body is one unit across; collision margins 1e-3 units; contact
//   breaking threshold 1e-9 units (contacts only on touch: speculative contacts ate the restitution).
#include <btBulletDynamicsCommon.h>

#include <chrono>
#include <cmath>

#include "engine.hpp"

namespace grainlab {

namespace {

struct ObjectInfo {
  const Scene* scene = nullptr;
  int material = 0;
  double mass = 0;       // 0: wall
  std::int64_t id = -1;  // body id; wall or plane k: -1 - k
};

bool pair_material(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int, int,
                   const btCollisionObjectWrapper* b, int, int) {
  const auto* ia = static_cast<const ObjectInfo*>(a->getCollisionObject()->getUserPointer());
  const auto* ib = static_cast<const ObjectInfo*>(b->getCollisionObject()->getUserPointer());
  if (!ia || !ib) return false;
  const Material& m = ia->scene->pair(ia->material, ib->material);
  const double meff = ia->mass == 0   ? ib->mass
                      : ib->mass == 0 ? ia->mass
                                      : ia->mass * ib->mass / (ia->mass + ib->mass);
  cp.m_combinedRestitution = impulse_engine_restitution(m, meff);
  cp.m_combinedFriction = ia->scene->effects.has(Effect::friction) ? m.mu : 0.0;
  return true;
}

class BulletEngine final : public Engine {
 public:
  BulletEngine(const Scene& scene, std::vector<BodySpec> bodies)
      : scene_(scene),
        bodies_(std::move(bodies)),
        dispatcher_(&config_),
        world_(&dispatcher_, &broadphase_, &solver_, &config_) {
    gContactAddedCallback = pair_material;
    // Contacts only where bodies touch: with Bullet's default breaking threshold (0.02 units) a
    // speculative contact brakes an approaching grain before it touches, leaving restitution nothing to
    // reverse (a 50 cm/s impact came to rest with e = 0.7).
    gContactBreakingThreshold = 1e-9;
    if (three_d()) {
      scale_ = unit_per_median_diameter(scene_.bodies3d);
      const Vec3 g = scene_.effects.has(Effect::gravity) ? Vec3(scene_.gravity3d * scale_) : Vec3::Zero();
      world_.setGravity(btVector3(g.x(), g.y(), g.z()));
    } else {
      scale_ = unit_per_median_diameter(bodies_);
      const Vec2 g = scene_.effects.has(Effect::gravity) ? scene_.gravity * scale_ : Vec2{};
      world_.setGravity(btVector3(g.x, g.y, 0));
    }
    btContactSolverInfo& info = world_.getSolverInfo();
    info.m_restitutionVelocityThreshold = 0;
    // Penetration is always corrected by split impulse (pseudo-velocities that add no kinetic energy):
    // below Bullet's default threshold (-0.04 units) Baumgarte feedback in the real velocity pushed a
    // 50 cm/s bounce from the scene's e = 0.7 to 0.9.
    info.m_splitImpulse = scene_.accuracy.split_impulse;
    info.m_splitImpulsePenetrationThreshold = 0;
    info.m_numIterations = scene_.accuracy.velocity_iterations;
    if (scene_.accuracy.erp) info.m_erp = info.m_erp2 = *scene_.accuracy.erp;
    info_.reserve(bodies_.size() + scene_.walls.size() + scene_.bodies3d.size() + scene_.planes.size());
    for (const BodySpec& b : bodies_) add_body(b);
    for (const WallSpec& w : scene_.walls) add_wall(w);
    for (const Body3Spec& b : scene_.bodies3d) add_body3d(b);
    if (three_d()) shape_of_ = polyhedron_indices(scene_.bodies3d);
    for (const PlaneSpec& p : scene_.planes) {
      auto shape = std::make_unique<btStaticPlaneShape>(btVector3(p.normal.x(), p.normal.y(), p.normal.z()),
                                                        p.normal.dot(p.point) * scale_);
      shape->setMargin(1e-3);
      btTransform at;
      at.setIdentity();
      add(std::move(shape), 0.0, btVector3(0, 0, 0), at,
          {&scene_, p.material, 0.0, -1 - static_cast<std::int64_t>(&p - scene_.planes.data())});
    }
  }
  ~BulletEngine() override {
    for (auto& b : rigid_) world_.removeRigidBody(b.get());
  }

  std::string name() const override { return "bullet"; }
  std::string integrator() const override { return "bullet sequential impulses (semi-implicit Euler)"; }
  double time() const override { return t_; }

  void advance_to(double t_end) override {
    const auto start = std::chrono::steady_clock::now();
    const double h = scene_.accuracy.dt / scene_.accuracy.substeps;
    while (t_ + h * (1 - 1e-3) <= t_end) {
      move_walls(h);
      world_.stepSimulation(h, 0);  // maxSubSteps = 0: exactly one step of h, no interpolation
      t_ += h;
      ++steps_;
      if (tracking_contacts()) record_contacts(t_, h, step_impulses());
    }
    wall_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  Frame frame() const override {
    Frame f;
    f.time = t_;
    if (three_d()) return frame3d(f);
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const btRigidBody& b = *rigid_[k];
      const btVector3 p = b.getCenterOfMassPosition(), v = b.getLinearVelocity(), w = b.getAngularVelocity();
      btScalar yaw, pitch, roll;
      b.getCenterOfMassTransform().getBasis().getEulerZYX(yaw, pitch, roll);
      f.add_body(bodies_[k].id, p.x() / scale_, p.y() / scale_, v.x() / scale_, v.y() / scale_, yaw, w.z(),
                 bodies_[k].radius, shape_of_[k]);
    }
    return f;
  }

  EnergyReport energies() const override {
    return three_d() ? rigid_body_energies(frame(), scene_.bodies3d, scene_)
                     : rigid_body_energies(frame(), bodies_, scene_);
  }

  std::map<std::string, double> diagnostics() const override {
    return {{"steps", double(steps_)},
            {"rejected_steps", 0.0},
            {"force_evaluations", double(steps_)},
            {"contacts", double(dispatcher_.getNumManifolds())},
            {"solver_iterations", double(scene_.accuracy.velocity_iterations)},
            {"wall_seconds", wall_seconds_},
            {"length_scale_units_per_cm", scale_},
            {"particles", double(bodies_.size() + scene_.bodies3d.size())}};
  }
  std::vector<std::vector<double>> polygon_shapes() const override {
    return three_d() ? polyhedron_vertices(scene_.bodies3d) : polygon_outlines(bodies_);
  }

 private:
  bool three_d() const { return scene_.dimension == 3; }

  // Normal impulses of the last step per touching pair, in cgs (Bullet's are in g x units/s).
  PairImpulses step_impulses() const {
    PairImpulses out;
    for (int m = 0; m < dispatcher_.getNumManifolds(); ++m) {
      const btPersistentManifold* man = dispatcher_.getManifoldByIndexInternal(m);
      const auto* a = static_cast<const ObjectInfo*>(man->getBody0()->getUserPointer());
      const auto* b = static_cast<const ObjectInfo*>(man->getBody1()->getUserPointer());
      double sum = 0;
      for (int k = 0; k < man->getNumContacts(); ++k) sum += man->getContactPoint(k).getAppliedImpulse();
      if (sum > 0 && a && b) out[{a->id, b->id}] += sum / scale_;
    }
    return out;
  }

  // Bullet's body frame is the principal frame; principal_[k] turns it into the scene's body frame.
  Frame frame3d(Frame& f) const {
    for (std::size_t k = 0; k < scene_.bodies3d.size(); ++k) {
      const btRigidBody& b = *rigid_[k];
      const btVector3 p = b.getCenterOfMassPosition() / scale_, v = b.getLinearVelocity() / scale_;
      const btVector3 w = b.getAngularVelocity();
      const btQuaternion bq = b.getOrientation();
      const Quat q = (Quat(bq.w(), bq.x(), bq.y(), bq.z()) * principal_[k].conjugate()).normalized();
      append_body3d(f, scene_.bodies3d[k], shape_of_[k], Vec3(p.x(), p.y(), p.z()), Vec3(v.x(), v.y(), v.z()),
                    q, Vec3(w.x(), w.y(), w.z()));
    }
    return f;
  }

  // A 3-D body. Bullet takes a diagonal inertia in the body frame, so the body frame becomes the
  // principal frame (eigenvectors V of the scene's tensor): the hull's vertices are written in it
  // (V^T v) and the initial orientation is q V.
  void add_body3d(const Body3Spec& s) {
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(s.inertia);
    Mat3 V = eig.eigenvectors();
    if (V.determinant() < 0) V.col(2) *= -1;
    const Quat principal(V);
    principal_.push_back(principal);
    std::unique_ptr<btCollisionShape> shape;
    if (s.shape == Body3Spec::Shape::Sphere) {
      shape = std::make_unique<btSphereShape>(s.radius * scale_);
    } else {
      auto hull = std::make_unique<btConvexHullShape>();
      for (const Vec3& v : s.hull.vertices) {
        const Vec3 u = V.transpose() * v * scale_;
        hull->addPoint(btVector3(u.x(), u.y(), u.z()), false);
      }
      hull->recalcLocalAabb();
      hull->setMargin(1e-3);
      shape = std::move(hull);
    }
    const Vec3 I = eig.eigenvalues() * scale_ * scale_;
    const Quat q = (s.orientation * principal).normalized();
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(s.position.x() * scale_, s.position.y() * scale_, s.position.z() * scale_));
    at.setRotation(btQuaternion(q.x(), q.y(), q.z(), q.w()));
    add(std::move(shape), s.mass, btVector3(I.x(), I.y(), I.z()), at, {&scene_, s.material, s.mass, s.id});
    btRigidBody& b = *rigid_.back();
    const Vec3 v = s.velocity * scale_, w = scene_.effects.has(Effect::rotation) ? s.spin : Vec3::Zero();
    b.setLinearVelocity(btVector3(v.x(), v.y(), v.z()));
    b.setAngularVelocity(btVector3(w.x(), w.y(), w.z()));
    if (!scene_.effects.has(Effect::rotation)) b.setAngularFactor(btVector3(0, 0, 0));
    // Explicit gyroscopic forces are off by default in Bullet; without them a torque-free asymmetric
    // body keeps a constant angular velocity instead of precessing. The implicit body-frame form
    // conserves angular momentum best of the three Bullet offers.
    b.setFlags(b.getFlags() | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
  }

  void add(std::unique_ptr<btCollisionShape> shape, double mass, const btVector3& inertia,
           const btTransform& at, ObjectInfo info) {
    info_.push_back(info);
    btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape.get(), inertia);
    ci.m_startWorldTransform = at;
    auto body = std::make_unique<btRigidBody>(ci);
    body->setUserPointer(&info_.back());
    body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK);
    body->setActivationState(DISABLE_DEACTIVATION);
    body->setContactProcessingThreshold(0);
    if (!scene_.effects.has(Effect::normal_contact))
      body->setCollisionFlags(body->getCollisionFlags() | btCollisionObject::CF_NO_CONTACT_RESPONSE);
    world_.addRigidBody(body.get());
    shapes_.push_back(std::move(shape));
    rigid_.push_back(std::move(body));
  }

  void add_body(const BodySpec& s) {
    std::unique_ptr<btCollisionShape> shape;
    if (s.shape == BodySpec::Shape::Disc) {
      shape = std::make_unique<btSphereShape>(s.radius * scale_);
    } else {  // a prism one unit deep, its section the polygon; only its in-plane motion is free
      auto hull = std::make_unique<btConvexHullShape>();
      for (Vec2 v : s.vertices)
        for (double z : {-0.5, 0.5}) hull->addPoint(btVector3(v.x * scale_, v.y * scale_, z), false);
      hull->recalcLocalAabb();
      hull->setMargin(1e-3);
      shape = std::move(hull);
      ++polygons_;
    }
    const double I = s.inertia * scale_ * scale_;
    btTransform at;
    at.setIdentity();
    at.setOrigin(btVector3(s.position.x * scale_, s.position.y * scale_, 0));
    at.setRotation(btQuaternion(btVector3(0, 0, 1), s.angle));
    shape_of_.push_back(s.shape == BodySpec::Shape::Disc ? -1 : polygons_ - 1);
    add(std::move(shape), s.mass, btVector3(I, I, I), at, {&scene_, s.material, s.mass, s.id});
    btRigidBody& b = *rigid_.back();
    b.setLinearFactor(btVector3(1, 1, 0));
    b.setAngularFactor(scene_.effects.has(Effect::rotation) ? btVector3(0, 0, 1) : btVector3(0, 0, 0));
    b.setLinearVelocity(btVector3(s.velocity.x * scale_, s.velocity.y * scale_, 0));
    b.setAngularVelocity(btVector3(0, 0, scene_.effects.has(Effect::rotation) ? s.spin : 0.0));
  }

  void add_wall(const WallSpec& w) {
    btTransform at;
    at.setIdentity();
    std::unique_ptr<btCollisionShape> shape;
    if (w.kind == WallSpec::Kind::Line) {
      shape = std::make_unique<btStaticPlaneShape>(btVector3(w.b.x, w.b.y, 0), dot(w.b, w.a) * scale_);
    } else {
      const Vec2 d = w.b - w.a, c = (w.a + w.b) * 0.5;
      shape = std::make_unique<btBoxShape>(btVector3(0.5 * norm(d) * scale_, 5e-4, 1.0));
      at.setOrigin(btVector3(c.x * scale_, c.y * scale_, 0));
      at.setRotation(btQuaternion(btVector3(0, 0, 1), std::atan2(d.y, d.x)));
    }
    shape->setMargin(1e-3);
    add(std::move(shape), 0.0, btVector3(0, 0, 0), at,
        {&scene_, w.material, 0.0, -1 - static_cast<std::int64_t>(&w - scene_.walls.data())});
    if (w.motion.active()) {  // kinematic: Bullet derives its velocity from the motion state each step
      btRigidBody& b = *rigid_.back();
      motion_states_.push_back(std::make_unique<btDefaultMotionState>(at));
      b.setMotionState(motion_states_.back().get());
      b.setCollisionFlags(b.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      moving_.push_back({&b, &w, at});
    }
  }

  // Place kinematic walls where they must be at the end of the coming step.
  void move_walls(double h) {
    for (const Moving& m : moving_) {
      btTransform at = m.rest;
      const Vec2 d = wall_offset(m.spec->motion, t_ + h) * scale_;
      at.setOrigin(at.getOrigin() + btVector3(d.x, d.y, 0));
      m.body->getMotionState()->setWorldTransform(at);
    }
  }

  Scene scene_;
  std::vector<BodySpec> bodies_;
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  std::vector<ObjectInfo> info_;  // reserved up front: bodies point into it
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> rigid_;
  struct Moving {
    btRigidBody* body;
    const WallSpec* spec;
    btTransform rest;
  };
  std::vector<Moving> moving_;
  std::vector<std::unique_ptr<btDefaultMotionState>> motion_states_;
  std::vector<std::int32_t> shape_of_;  // per body: -1 disc or sphere, else index into the shapes
  std::vector<Quat> principal_;         // 3-D: principal frame in the scene's body frame
  int polygons_ = 0;
  double scale_ = 1, t_ = 0, wall_seconds_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace

std::unique_ptr<Engine> make_bullet_engine(const Scene& scene, std::vector<BodySpec> bodies) {
  return std::make_unique<BulletEngine>(scene, std::move(bodies));
}

}  // namespace grainlab
