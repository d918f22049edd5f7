// ODE 0.16.2 (double precision) behind the Engine interface. Mapping decisions (docs/engines.md):
// - 2-D scenes: every body is held in the z = 0 plane by a plane-2D joint; discs are spheres (a sphere
//   cut by the plane touches lines and other spheres exactly as a disc does).
// - Walls: a line is a plane; a segment is a thin box (ODE has no 2-D segment).
// - Materials: the near callback sets every contact's mu and bounce from the scene's pair material
//   (ODE has no mixing rules); bounce_vel = 0 so slow impacts keep their restitution; auto-disable
//   (sleeping) off.
// - Units: lengths scaled so a median body is one unit across; time and mass unchanged.
#include <ode/ode.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>

#include "engine.hpp"

namespace grainlab {

namespace {

struct GeomInfo {
  int material = 0;
  double mass = 0;       // 0: wall
  std::int64_t id = -1;  // body id; wall or plane k: -1 - k
};

class OdeEngine final : public Engine {
 public:
  OdeEngine(const Scene& scene, std::vector<BodySpec> bodies) : scene_(scene), bodies_(std::move(bodies)) {
    for (const WallSpec& w : scene_.walls)
      if (w.kind == WallSpec::Kind::Line && w.motion.active())
        throw InputError(
            w.where, "walls.motion",
            "engine \"ode\" cannot move a line wall (ODE planes are not placeable); use a segment");
    dInitODE2(0);
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    if (three_d()) {
      scale_ = unit_per_median_diameter(scene_.bodies3d);
      const Vec3 g = scene_.effects.has(Effect::gravity) ? Vec3(scene_.gravity3d * scale_) : Vec3::Zero();
      dWorldSetGravity(world_, g.x(), g.y(), g.z());
    } else {
      scale_ = unit_per_median_diameter(bodies_);
      const Vec2 g = scene_.effects.has(Effect::gravity) ? scene_.gravity * scale_ : Vec2{};
      dWorldSetGravity(world_, g.x, g.y, 0);
    }
    dWorldSetAutoDisableFlag(world_, 0);
    // ERP corrects penetration through real velocity: a grain resting 1.5e-3 cm into a wall was
    // launched at 30 cm/s. Capping the correcting velocity (0.05 body sizes per second) keeps recovery
    // from injecting energy; a deep overlap then resolves over several steps instead of one.
    dWorldSetContactMaxCorrectingVel(world_, 0.05);
    if (quick()) dWorldSetQuickStepNumIterations(world_, scene_.accuracy.velocity_iterations);
    if (scene_.accuracy.erp) dWorldSetERP(world_, *scene_.accuracy.erp);
    if (scene_.accuracy.cfm) dWorldSetCFM(world_, *scene_.accuracy.cfm);
    info_.reserve(bodies_.size() + scene_.walls.size() + scene_.bodies3d.size() + scene_.planes.size());
    for (const BodySpec& b : bodies_) add_body(b);
    for (const WallSpec& w : scene_.walls) add_wall(w);
    for (const Body3Spec& b : scene_.bodies3d) add_body3d(b);
    if (three_d()) shape_of_ = polyhedron_indices(scene_.bodies3d);
    for (const PlaneSpec& p : scene_.planes) {
      info_.push_back({p.material, 0.0, -1 - static_cast<std::int64_t>(&p - scene_.planes.data())});
      dGeomSetData(
          dCreatePlane(space_, p.normal.x(), p.normal.y(), p.normal.z(), p.normal.dot(p.point) * scale_),
          &info_.back());
    }
  }
  ~OdeEngine() override {
    dJointGroupDestroy(contacts_);
    dSpaceDestroy(space_);
    dWorldDestroy(world_);
  }

  std::string name() const override { return "ode"; }
  std::string integrator() const override { return quick() ? "ode dWorldQuickStep" : "ode dWorldStep"; }
  double time() const override { return t_; }

  void advance_to(double t_end) override {
    const auto start = std::chrono::steady_clock::now();
    const double h = scene_.accuracy.dt / scene_.accuracy.substeps;
    while (t_ + h * (1 - 1e-3) <= t_end) {
      move_walls(h);
      dSpaceCollide(space_, this, &OdeEngine::near_callback);
      if (quick())
        dWorldQuickStep(world_, h);
      else
        dWorldStep(world_, h);
      t_ += h;
      ++steps_;
      if (tracking_contacts()) record_contacts(t_, h, step_impulses(h));
      feedback_.clear();
      dJointGroupEmpty(contacts_);
    }
    wall_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  Frame frame() const override {
    Frame f;
    f.time = t_;
    if (three_d()) return frame3d(f);
    for (std::size_t k = 0; k < bodies_.size(); ++k) {
      const dReal* p = dBodyGetPosition(handles_[k]);
      const dReal* v = dBodyGetLinearVel(handles_[k]);
      const dReal* w = dBodyGetAngularVel(handles_[k]);
      const dReal* R = dBodyGetRotation(handles_[k]);
      f.add_body(bodies_[k].id, p[0] / scale_, p[1] / scale_, v[0] / scale_, v[1] / scale_,
                 std::atan2(R[4], R[0]), w[2], bodies_[k].radius, shape_of_[k]);
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
            {"contacts", double(last_contacts_)},
            {"wall_seconds", wall_seconds_},
            {"length_scale_units_per_cm", scale_},
            {"solver_iterations", double(scene_.accuracy.velocity_iterations)},
            {"particles", double(bodies_.size() + scene_.bodies3d.size())}};
  }
  std::vector<std::vector<double>> polygon_shapes() const override {
    return three_d() ? polyhedron_vertices(scene_.bodies3d) : polygon_outlines(bodies_);
  }

 private:
  // "auto": the direct solver where it is affordable. dWorldStep factors a dense matrix over all
  // constraint rows (3 per frictional contact): 300 settled discs took over 300 s for 250 steps, where
  // dWorldQuickStep took 3 s for 2,500.
  static constexpr std::size_t kDirectStepperMaxBodies = 32;
  bool quick() const {
    const std::string& s = scene_.accuracy.stepper;
    return s == "quick" || (s == "auto" && bodies_.size() + scene_.bodies3d.size() > kDirectStepperMaxBodies);
  }

  // Normal impulses of the last step per touching pair, in cgs, from the contact joints' feedback.
  PairImpulses step_impulses(double h) const {
    PairImpulses out;
    for (const Feedback& f : feedback_) {
      const double fn = f.normal.x() * f.fb.f1[0] + f.normal.y() * f.fb.f1[1] + f.normal.z() * f.fb.f1[2];
      if (fn > 0) out[{f.a, f.b}] += fn * h / scale_;
    }
    return out;
  }
  bool three_d() const { return scene_.dimension == 3; }

  Frame frame3d(Frame& f) const {
    for (std::size_t k = 0; k < handles_.size(); ++k) {
      const dReal *p = dBodyGetPosition(handles_[k]), *v = dBodyGetLinearVel(handles_[k]);
      const dReal *w = dBodyGetAngularVel(handles_[k]), *q = dBodyGetQuaternion(handles_[k]);
      append_body3d(f, scene_.bodies3d[k], shape_of_[k], Vec3(p[0], p[1], p[2]) / scale_,
                    Vec3(v[0], v[1], v[2]) / scale_, Quat(q[0], q[1], q[2], q[3]), Vec3(w[0], w[1], w[2]));
    }
    return f;
  }

  // A 3-D body: ODE wants the body origin at the centre of mass, which is the scene's body frame too, so
  // the full inertia tensor goes in as it is and the geometry needs no offset.
  void add_body3d(const Body3Spec& s) {
    dBodyID b = dBodyCreate(world_);
    dMass m;
    const Mat3 I = s.inertia * scale_ * scale_;
    dMassSetParameters(&m, s.mass, 0, 0, 0, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
    dBodySetMass(b, &m);
    const Vec3 x = s.position * scale_, v = s.velocity * scale_;
    dBodySetPosition(b, x.x(), x.y(), x.z());
    dBodySetLinearVel(b, v.x(), v.y(), v.z());
    const dQuaternion q = {s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z()};
    dBodySetQuaternion(b, q);
    const Vec3 w = scene_.effects.has(Effect::rotation) ? s.spin : Vec3::Zero();
    dBodySetAngularVel(b, w.x(), w.y(), w.z());
    dBodySetAutoDisableFlag(b, 0);
    if (!scene_.effects.has(Effect::rotation)) dBodySetMaxAngularSpeed(b, 0);
    // Torque-free bodies keep L exactly only with the gyroscopic term on (ODE's default, stated here).
    dBodySetGyroscopicMode(b, 1);
    info_.push_back({s.material, s.mass, s.id});
    dGeomID g =
        s.shape == Body3Spec::Shape::Sphere ? dCreateSphere(space_, s.radius * scale_) : convex(s.hull);
    dGeomSetBody(g, b);
    dGeomSetData(g, &info_.back());
    if (!scene_.effects.has(Effect::normal_contact)) dGeomSetCategoryBits(g, 0);
    handles_.push_back(b);
  }

  dGeomID convex(const Polyhedron& h) {
    Convex& c = convexes_.emplace_back();
    for (const Vec3& v : h.vertices)
      c.points.insert(c.points.end(), {v.x() * scale_, v.y() * scale_, v.z() * scale_});
    for (std::size_t f = 0; f < h.faces.size(); ++f) {
      const Vec3& n = h.normals[f];
      c.planes.insert(c.planes.end(), {n.x(), n.y(), n.z(), h.offsets[f] * scale_});
      c.polygons.push_back(static_cast<unsigned>(h.faces[f].size()));
      for (int i : h.faces[f]) c.polygons.push_back(static_cast<unsigned>(i));
    }
    return dCreateConvex(space_, c.planes.data(), static_cast<unsigned>(h.faces.size()), c.points.data(),
                         static_cast<unsigned>(h.vertices.size()), c.polygons.data());
  }

  void add_body(const BodySpec& s) {
    dBodyID b = dBodyCreate(world_);
    dMass m;
    const double I = s.inertia * scale_ * scale_;
    // Full inertia of the disc as a 3-D body; only I_zz acts under the plane-2D joint.
    dMassSetParameters(&m, s.mass, 0, 0, 0, I, I, I, 0, 0, 0);
    dBodySetMass(b, &m);
    dBodySetPosition(b, s.position.x * scale_, s.position.y * scale_, 0);
    dBodySetLinearVel(b, s.velocity.x * scale_, s.velocity.y * scale_, 0);
    dMatrix3 R;
    dRFromAxisAndAngle(R, 0, 0, 1, s.angle);
    dBodySetRotation(b, R);
    dBodySetAngularVel(b, 0, 0, scene_.effects.has(Effect::rotation) ? s.spin : 0.0);
    dBodySetAutoDisableFlag(b, 0);
    if (!scene_.effects.has(Effect::rotation)) dBodySetMaxAngularSpeed(b, 0);
    dJointID plane = dJointCreatePlane2D(world_, nullptr);
    dJointAttach(plane, b, nullptr);
    info_.push_back({s.material, s.mass, s.id});
    dGeomID g =
        s.shape == BodySpec::Shape::Disc ? dCreateSphere(space_, s.radius * scale_) : prism(s.vertices);
    shape_of_.push_back(s.shape == BodySpec::Shape::Disc ? -1 : prisms_ - 1);
    dGeomSetBody(g, b);
    dGeomSetData(g, &info_.back());
    if (!scene_.effects.has(Effect::normal_contact)) dGeomSetCategoryBits(g, 0);
    handles_.push_back(b);
  }

  // A convex prism one unit deep with the polygon as its section. ODE keeps pointers to the arrays,
  // so they live in the engine (std::deque: stable addresses).
  dGeomID prism(const std::vector<Vec2>& poly) {
    const std::size_t n = poly.size();
    const double h = 0.5;
    Convex& c = convexes_.emplace_back();
    for (double z : {-h, h})
      for (Vec2 v : poly) c.points.insert(c.points.end(), {v.x * scale_, v.y * scale_, z});
    auto face = [&](double nx, double ny, double nz, double d, std::vector<unsigned> idx) {
      c.planes.insert(c.planes.end(), {nx, ny, nz, d});
      c.polygons.push_back(static_cast<unsigned>(idx.size()));
      c.polygons.insert(c.polygons.end(), idx.begin(), idx.end());
    };
    std::vector<unsigned> top, bottom;
    for (std::size_t i = 0; i < n; ++i)
      top.push_back(static_cast<unsigned>(n + i)), bottom.push_back(static_cast<unsigned>(n - 1 - i));
    face(0, 0, 1, h, top);
    face(0, 0, -1, h, bottom);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      const Vec2 e = poly[j] - poly[i];
      const Vec2 out = Vec2{e.y, -e.x} * (1 / norm(e));  // outward for a counter-clockwise polygon
      face(out.x, out.y, 0, dot(out, poly[i]) * scale_,
           {static_cast<unsigned>(i), static_cast<unsigned>(j), static_cast<unsigned>(n + j),
            static_cast<unsigned>(n + i)});
    }
    ++prisms_;
    return dCreateConvex(space_, c.planes.data(), static_cast<unsigned>(c.planes.size() / 4), c.points.data(),
                         static_cast<unsigned>(c.points.size() / 3), c.polygons.data());
  }

  void add_wall(const WallSpec& w) {
    info_.push_back({w.material, 0.0, -1 - static_cast<std::int64_t>(&w - scene_.walls.data())});
    dGeomID g;
    if (w.kind == WallSpec::Kind::Line) {
      g = dCreatePlane(space_, w.b.x, w.b.y, 0, dot(w.b, w.a) * scale_);
    } else {  // a thin box along the segment, thickness 1e-3 of a body size
      const Vec2 d = w.b - w.a, c = (w.a + w.b) * 0.5;
      const double thick = 1e-3;
      g = dCreateBox(space_, norm(d) * scale_, thick, 1.0);
      dMatrix3 R;
      dRFromAxisAndAngle(R, 0, 0, 1, std::atan2(d.y, d.x));
      if (w.motion.active()) {  // a kinematic body carries the box along the prescribed path
        dBodyID kb = dBodyCreate(world_);
        dBodySetKinematic(kb);
        dGeomSetBody(g, kb);
        dBodySetPosition(kb, c.x * scale_, c.y * scale_, 0);
        dBodySetRotation(kb, R);
        moving_.push_back({kb, &w, c});
      } else {
        dGeomSetPosition(g, c.x * scale_, c.y * scale_, 0);
        dGeomSetRotation(g, R);
      }
    }
    dGeomSetData(g, &info_.back());
  }

  // Kinematic walls move at the mean velocity of the step, landing exactly on the prescribed path.
  void move_walls(double h) {
    for (const Moving& m : moving_) {
      const Vec2 v = (wall_offset(m.spec->motion, t_ + h) - wall_offset(m.spec->motion, t_)) * (scale_ / h);
      const Vec2 p = (m.rest + wall_offset(m.spec->motion, t_)) * scale_;
      dBodySetPosition(m.body, p.x, p.y, 0);
      dBodySetLinearVel(m.body, v.x, v.y, 0);
    }
  }

  static void near_callback(void* data, dGeomID a, dGeomID b) {
    auto* self = static_cast<OdeEngine*>(data);
    const dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return;
    dContact c[8];
    const int n = dCollide(a, b, 8, &c[0].geom, sizeof(dContact));
    if (n == 0) return;
    const auto* ia = static_cast<const GeomInfo*>(dGeomGetData(a));
    const auto* ib = static_cast<const GeomInfo*>(dGeomGetData(b));
    const Material& m = self->scene_.pair(ia->material, ib->material);
    const double meff = ia->mass == 0   ? ib->mass
                        : ib->mass == 0 ? ia->mass
                                        : ia->mass * ib->mass / (ia->mass + ib->mass);
    for (int k = 0; k < n; ++k) {
      // dContactApprox1: mu is a coefficient (friction pyramid); without it ODE reads mu as a force limit.
      c[k].surface.mode = dContactBounce | dContactApprox1;
      c[k].surface.mu = self->scene_.effects.has(Effect::friction) ? m.mu : 0.0;
      c[k].surface.bounce = impulse_engine_restitution(m, meff);
      c[k].surface.bounce_vel = 0;
      dJointID j = dJointCreateContact(self->world_, self->contacts_, &c[k]);
      dJointAttach(j, ba, bb);
      if (self->tracking_contacts()) {  // f1 is the force on body 1 (the geom a's body)
        const dReal* n = c[k].geom.normal;
        Feedback& f = self->feedback_.emplace_back();
        f.a = ia->id, f.b = ib->id, f.normal = Vec3(n[0], n[1], n[2]);
        dJointSetFeedback(j, &f.fb);
        // ODE's normal points into geom a's body (a is pushed along +n); a wall geom has no body.
        if (!ba) f.normal = -f.normal;
      }
    }
    self->last_contacts_ = n;
  }

  Scene scene_;
  std::vector<BodySpec> bodies_;
  dWorldID world_;
  dSpaceID space_;
  dJointGroupID contacts_;
  std::vector<GeomInfo> info_;
  std::vector<dBodyID> handles_;
  struct Convex {
    std::vector<dReal> planes, points;
    std::vector<unsigned> polygons;
  };
  std::deque<Convex> convexes_;
  struct Feedback {
    std::int64_t a = -1, b = -1;
    Vec3 normal = Vec3::Zero();
    dJointFeedback fb{};
  };
  std::deque<Feedback> feedback_;  // stable addresses: ODE writes into them during the step
  struct Moving {
    dBodyID body;
    const WallSpec* spec;
    Vec2 rest;  // centre at rest, scene units
  };
  std::vector<Moving> moving_;
  std::vector<std::int32_t> shape_of_;  // per body: -1 disc or sphere, else index into the shapes
  int prisms_ = 0;
  double scale_ = 1, t_ = 0, wall_seconds_ = 0;
  std::uint64_t steps_ = 0;
  int last_contacts_ = 0;
};

}  // namespace

std::unique_ptr<Engine> make_ode_engine(const Scene& scene, std::vector<BodySpec> bodies) {
  return std::make_unique<OdeEngine>(scene, std::move(bodies));
}

}  // namespace grainlab
