#pragma once
// The scene model: what a scene file says, checked, and converted to cgs (cm, g, s) whatever units
// the file was written in (Scene::units says which, for converting results back). Engines build their own
// state from it; nothing here knows about any engine.
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "effects.hpp"
#include "input_error.hpp"
#include "polyhedron.hpp"
#include "vec2.hpp"

namespace grainlab {

// The fluid around the grains (effects wind_drag and buoyancy). In 2-D each disc stands for a sphere of
// the same radius and `grain_density`, so drag and buoyancy act as the accelerations they give that sphere.
struct FluidSpec {
  double density = 0.00123;     // g/cm^3 (air)
  double viscosity = 0.146;     // kinematic, cm^2/s
  double grain_density = 2.65;  // g/cm^3, of the grains the bodies stand for
};

// The wind of effect wind_drag: a horizontally averaged profile u(y) over the bed, its shear stress
// reduced by the grains' drag (docs/saltation.md, "DEM saltation").
struct WindSpec {
  // Fixed: the clean log law, no feedback. MixingLength: the thesis's tau = rho (kappa z du/dz)^2 with
  // the grains' drag taken out of it. VanDriest: l = kappa z (1 - exp(-z u*/(26 nu))) plus molecular
  // viscosity (Huo et al. 2021).
  enum class Model { Fixed, MixingLength, VanDriest };
  enum class DragLaw { Thesis, DallaValle, Huo2021 };
  Model model = Model::MixingLength;
  DragLaw drag_law = DragLaw::Thesis;  // Thesis: eqs 4.30-4.31; DallaValle: (0.63 + 4.8/sqrt(Re))^2;
                                       // Huo2021: (sqrt(0.5) + sqrt(24/Re))^2
  double u_star = 0;                   // cm/s, shear velocity above the grains
  double kappa = 0.4;
  double roughness = 0;           // cm; 0: median grain diameter / 30 (the thesis's y0)
  double bin_height = 0;          // cm, the wind's cells; 0: median grain radius
  double top = 0;                 // cm above the bed; 0: 400 median diameters
  double update_interval = 1e-4;  // s between wind updates
  // The air's own inertia: false (default) solves the steady column for the drag of the last interval
  // at every update (the thesis's steady-state wind); true advances rho du/dt by update_interval (the
  // DEM literature's form; the column's stored momentum then takes seconds to drain from the clean
  // profile).
  bool inertia = false;
  double thickness = 0;             // cm, the slab a 2-D bed stands for; 0: median grain diameter
  std::optional<double> bed_level;  // cm; unset: found from the grains' packing every update
};

// How the velocity-dependent part of a contact force is specified. All three end up as a force
// coefficient c(m_eff) in g/s, so f_damp = -c v (see docs/physics.md, "damping convention").
struct Damping {
  enum class Kind { None, Rate, Coefficient, Restitution };
  Kind kind = Kind::None;
  double value = 0;  // Rate: gamma in 1/s (multiplied by m_eff); Coefficient: g/s; Restitution: eps
};

struct Material {
  std::string name;
  double k_n = 0;  // normal stiffness, force/length
  Damping normal_damping;
  double k_s = 0;  // tangential (shear) spring stiffness, force/length
  Damping shear_damping;
  double mu = 0;  // friction coefficient (static = kinetic, as in the thesis)
};

enum class Integrator { PredictorCorrector, VelocityVerlet };
// What the predictor-corrector's velocity difference is measured against (docs/physics.md): the
// corrected velocity itself (reproduces the thesis's ~36 steps per collision) or its change over the step.
enum class ErrorMeasure { Velocity, Change };

struct Accuracy {
  Integrator integrator = Integrator::PredictorCorrector;
  double tolerance = 0.005;  // predictor-corrector: allowed fractional velocity difference per step
  ErrorMeasure error_measure = ErrorMeasure::Velocity;
  double velocity_floor =
      1e-6;               // predictor-corrector: absolute velocity change below which ratios are not trusted
  double dt = 1e-5;       // Verlet: the step; predictor-corrector: the first step
  double dt_min = 1e-12;  // predictor-corrector: below this the run stops with an error
  double dt_max = 1e-2;   // predictor-corrector: cap on the growing step
  std::optional<double> skin;  // neighbour-list skin (length); default 0.25 x smallest grain radius
  // Impulse engines (docs/engines.md): solver iterations and sub-steps per dt.
  int velocity_iterations = 8, position_iterations = 3, substeps = 1;
  // ODE: "step" (dWorldStep, direct LCP), "quick" (dWorldQuickStep, iterative) or "auto": step for
  // few-body scenes, quick beyond (dWorldStep's dense LCP grows as the cube of the contact count).
  std::string stepper = "auto";
  // Penetration feedback of the impulse engines (docs/engines.md): ODE's and Bullet's error reduction
  // parameter, ODE's constraint force mixing, Bullet's split impulse. Unset: the engine's default.
  std::optional<double> erp, cfm;
  bool split_impulse = true;
};

// Sinusoidal prescribed motion x(t) = x0 + amplitude sin(2 pi f t + phase), per axis.
struct Motion {
  Vec2 amplitude{};
  double frequency = 0;
  Vec2 phase{};  // radians, per axis
  bool active() const { return frequency != 0 && (amplitude.x != 0 || amplitude.y != 0); }
};

struct BodySpec {
  enum class Shape { Disc, Polygon };
  std::int64_t id = -1;
  Shape shape = Shape::Disc;
  double radius = 0;           // disc radius
  std::vector<Vec2> vertices;  // polygon, counter-clockwise, relative to the centroid (body frame)
  double mass = 0;             // per unit thickness in 2-D
  double inertia = 0;          // about the centre of mass
  Vec2 position{}, velocity{};
  double angle = 0, spin = 0;
  int material = 0;  // index into Scene::materials
  SourceLocation where;
};

// A 3-D rigid body. The body frame has its origin at the centre of mass; `hull` (polyhedra) is given
// in that frame, so a loaded body's geometric centre sits at -centre_of_mass_offset.
struct Body3Spec {
  enum class Shape { Sphere, Polyhedron };
  std::int64_t id = -1;
  Shape shape = Shape::Sphere;
  double radius = 0;  // sphere radius; polyhedron: bounding radius about the centre of mass
  Polyhedron hull;
  double mass = 0;
  Mat3 inertia = Mat3::Identity();  // about the centre of mass, in body axes
  Vec3 position = Vec3::Zero(), velocity = Vec3::Zero();
  Quat orientation = Quat::Identity();  // body to world
  Vec3 spin = Vec3::Zero();             // angular velocity, world frame
  int material = 0;
  // Held in place: the body never moves (no step changes its position, orientation or velocity), yet it
  // pushes back on the bodies that touch it as a body of its mass would (the contact's damping uses its
  // mass). What an impact's surroundings are when only the grains near the impact are simulated
  // (ImpactOptions::active_radius); not read from scene files. Native engine only.
  bool held = false;
  SourceLocation where;
};

// Sinusoidal prescribed motion of a 3-D plane, per axis: point(t) = point + amplitude sin(2 pi f t + phase).
struct Motion3 {
  Vec3 amplitude = Vec3::Zero();
  double frequency = 0;
  Vec3 phase = Vec3::Zero();  // radians, per axis
  bool active() const { return frequency != 0 && amplitude.squaredNorm() > 0; }
  // Displacement from rest and velocity at time t (zero for a plane at rest).
  Vec3 shift(double t) const {
    if (!active()) return Vec3::Zero();
    const double om = 2 * M_PI * frequency;
    return {amplitude.x() * std::sin(om * t + phase.x()), amplitude.y() * std::sin(om * t + phase.y()),
            amplitude.z() * std::sin(om * t + phase.z())};
  }
  Vec3 velocity(double t) const {
    if (!active()) return Vec3::Zero();
    const double om = 2 * M_PI * frequency;
    return {amplitude.x() * om * std::cos(om * t + phase.x()),
            amplitude.y() * om * std::cos(om * t + phase.y()),
            amplitude.z() * om * std::cos(om * t + phase.z())};
  }
  double reach() const { return amplitude.norm(); }  // how far the plane can move from rest
};

// An infinite plane wall in 3-D; bodies live on the side the normal points to. A moving plane keeps its
// normal and translates by `motion` (a vibrated floor, a shaken box).
struct PlaneSpec {
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitZ();
  Motion3 motion;
  int material = 0;
  SourceLocation where;
};

struct WallSpec {
  enum class Kind { Segment, Line };
  Kind kind = Kind::Segment;
  Vec2 a{}, b{};  // segment end points; for a line: a point on it and b = unit normal (front side)
  int material = 0;
  Motion motion;
  SourceLocation where;
};

struct SizeDistribution {
  enum class Kind { Fixed, Uniform, Normal };
  Kind kind = Kind::Fixed;
  double a = 0, b = 0;  // Fixed: radius a; Uniform: [a, b]; Normal: mean a, sd b (truncated to +-3 sd, > 0)
};

// Generated assemblies expand into bodies when an engine builds the scene.
struct AssemblySpec {
  enum class Kind { Lattice, Poured };
  Kind kind = Kind::Lattice;
  int nx = 0, ny = 0;      // lattice: columns, rows
  int count = 0;           // poured: number of discs
  double spacing = 0;      // lattice: centre spacing
  Vec2 origin{};           // lattice: first centre; poured: lower-left of the pouring box
  double width = 0;        // poured: width of the box discs are dropped into
  double settle_time = 0;  // poured: simulated time to let the pour settle
  SizeDistribution radius;
  double density = 0;    // 2-D density, mass per area; with `spheres`, mass per volume
  bool spheres = false;  // each disc has the mass and moment of inertia of the sphere of its radius
  Vec2 velocity{};
  // 3-D scenes (spheres; density is mass per volume): layers, the first centre or the pouring box's
  // lowest corner, the box's extent along y, and the velocity given to every sphere.
  int nz = 0;
  Vec3 origin3 = Vec3::Zero(), velocity3 = Vec3::Zero();
  double depth = 0;
  // 3-D poured beds of irregular convex grains instead of spheres: each grain is an icosahedron whose
  // vertices are moved by up to `irregularity` of the radius, stretched along three random axes by
  // factors 1 +- up to `elongation`, and scaled to the volume of the sphere of its drawn radius.
  bool polyhedra = false;
  double irregularity = 0.2, elongation = 0.2;
  int material = 0;
  SourceLocation where;
};

struct OutputSpec {
  std::string file;       // empty: derived from the scene file name
  int frames = 50;        // equally spaced frames over the duration, plus the initial one
  bool contacts = false;  // write every contact event (begin, end, impulse, peak force) to /contact_events
};

struct Scene {
  std::string path;                    // scene file
  std::string text;                    // the scene file's text as read
  std::vector<std::string> overrides;  // the --set assignments, in order
  std::string name;
  int dimension = 2;
  std::string units = "cgs";  // of the file: "cgs" or "si"; values below are always cgs
  // Factors from the file's units to cgs, for reporting results in the file's units.
  struct UnitScale {
    double length = 1, mass = 1, time = 1;
    double velocity() const { return length / time; }
    double energy() const { return mass * length * length / (time * time); }
  } to_cgs;
  double duration = 0;
  std::uint64_t seed = 0;
  Vec2 gravity{0, -981.0};                              // 2-D
  Vec3 gravity3d{0.0, 0.0, -981.0};                     // 3-D (z up)
  std::optional<std::pair<double, double>> periodic_x;  // [xmin, xmax)
  std::optional<std::pair<double, double>> periodic_y;  // [ymin, ymax), 3-D only
  bool clip_attractive_normal_force = false;
  double overlap_tolerance = 0.01;  // allowed initial overlap as a fraction of the smaller radius
  Effects effects;
  FluidSpec fluid;
  WindSpec wind;
  Accuracy accuracy;
  std::vector<Material> materials;
  std::map<std::pair<int, int>, Material> pair_materials;  // explicit pair materials, keyed (min, max)
  std::vector<BodySpec> bodies;
  std::vector<WallSpec> walls;
  std::vector<AssemblySpec> assemblies;
  std::vector<Body3Spec> bodies3d;  // 3-D scenes: [[bodies]]
  std::vector<PlaneSpec> planes;    // 3-D scenes: [[walls]] of type "plane"
  OutputSpec output;

  // The material acting between materials a and b. Same material: itself; otherwise the
  // explicit pair entry, which load_scene() has checked exists for every pair that can touch.
  const Material& pair(int a, int b) const;
};

// Reads and checks a scene file. `overrides` are "dotted.key=value" assignments whose value is TOML.
// Throws InputError naming file, line and key for anything wrong.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& text, const std::string& path,
                  const std::vector<std::string>& overrides = {});

}  // namespace grainlab
