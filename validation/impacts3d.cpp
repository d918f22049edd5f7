// Ch. III's impacts with spheres: the bed, one impact on the native 3-D engine, and their measures.
#include "impacts3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "cell_grid.hpp"
#include "engine.hpp"
#include "impact_bed.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
#include "rng.hpp"
#include "time_left.hpp"
#include "world3d.hpp"

namespace grainlab::validation {

const std::vector<std::string> kStageRunColumns = {"run", "x",  "y",  "z",  "qw", "qx", "qy",
                                                   "qz",  "vx", "vy", "vz", "wx", "wy", "wz"};

namespace {

constexpr double kDeg = M_PI / 180;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double sphere_mass(double density, double r) {
  return density * 4.0 / 3.0 * M_PI * r * r * r;
}

// The box of five planes and a material of stiffness k_n and restitution e (the thesis's friction),
// stepped at 1/30 of a contact; with a pour of the spec's spheres when `pour` is set.
std::string bed3d_text(const Bed3dSpec& s, double k_n, double e, double duration, bool pour) {
  const double m = sphere_mass(s.density, s.smallest_radius());
  std::string text = fmt::format(R"toml(
[scene]
name = "3-D impact bed ({} spheres)"
dimension = 3
duration = {}
seed = {}
effects = ["gravity", "normal_contact", {}"rotation"]
[accuracy]
integrator = "verlet"
dt = {}
[materials.sand]
k_n = {}
k_s = {}
mu = {}
restitution = {}
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [{}, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
[[walls]]
type = "plane"
point = [0.0, {}, 0.0]
normal = [0.0, -1.0, 0.0]
)toml",
                                 s.count, duration, s.seed, s.mu > 0 ? "\"friction\", " : "",
                                 contact_time(k_n, m, m) / 30, k_n, k_n, s.mu, e, s.width, s.depth);
  if (!pour) return text;
  text += fmt::format(
      "[[assemblies]]\ntype = \"poured\"\ncount = {}\nwidth = {}\ndepth = {}\norigin = [0.0, 0.0, 0.0]\n"
      "density = {}\nsettle_time = {}\n{}",
      s.count, s.width, s.depth, s.density, duration, s.polyhedra ? "shape = \"polyhedron\"\n" : "");
  if (s.radius_spread == 0) return text + fmt::format("radius = {}\n", s.radius);
  return text + fmt::format("[assemblies.radius_distribution]\nkind = \"uniform\"\nmin = {}\nmax = {}\n",
                            s.smallest_radius(), s.largest_radius());
}

std::vector<Body3Spec> at_rest(std::vector<Body3Spec> bodies) {
  for (Body3Spec& b : bodies) b.velocity = Vec3::Zero(), b.spin = Vec3::Zero();
  return bodies;
}

// A sphere's state as a finished run leaves it (a row of kStageRunColumns after the run's index), and back.
std::vector<double> motion_row(double run, const dem::Body3& b) {
  return {run,     b.x.x(), b.x.y(), b.x.z(), b.q.w(), b.q.x(), b.q.y(),
          b.q.z(), b.v.x(), b.v.y(), b.v.z(), b.w.x(), b.w.y(), b.w.z()};
}

void put_motion(const std::vector<double>& r, Body3Spec& b) {
  b.position = Vec3(r[1], r[2], r[3]), b.orientation = Quat(r[4], r[5], r[6], r[7]);
  b.velocity = Vec3(r[8], r[9], r[10]), b.spin = Vec3(r[11], r[12], r[13]);
}

// The runs of the bed within one stage of a build, each `duration` more of `k_n` and `e` handing the
// bodies back as they are then (moving or not). A stage continued from a checkpoint taken part-way
// through repeats its code from the stage's start: its finished runs hand back how they left the
// spheres, and the run it was in continues from its world's saved state, so the stage ends bit for bit
// as an unbroken one. While a run goes on, the stage hands its state to `save` every `every` seconds of
// the stage (its runs may each be shorter), and says how far the run has come to `progress` once a
// minute (a stage of a bed of irregular grains can take an hour), with the wall time left at its pace
// since the last report (a pour's first part, free fall, runs far faster than its end).
class StageRuns {
 public:
  using Save = std::function<void(const SampleTable&, const std::map<std::string, SampleTable>&)>;
  using Progress = std::function<void(double done, double duration, double seconds_left)>;
  StageRuns(Bed3dBuild& b, double every, Save save, BedRanks ranks, Progress progress = {})
      : done_(std::move(b.runs_done)),
        under_way_(std::move(b.run_under_way)),
        every_(every),
        save_(std::move(save)),
        progress_(std::move(progress)),
        ranks_(ranks) {
    b.runs_done = {}, b.run_under_way = {};
  }

  std::vector<Body3Spec> left_alone(const Bed3dSpec& s, std::vector<Body3Spec> bodies, double k_n, double e,
                                    double duration) {
    Scene scene = parse_scene(bed3d_text(s, k_n, e, duration, false), "3-D impact bed");
    scene.bodies3d = std::move(bodies);
    return run(std::move(scene), duration);
  }

  // The same for a scene of its own (the pour's settling), its bodies where the run starts.
  std::vector<Body3Spec> run(Scene scene, double duration) {
    const double run = static_cast<double>(next_run_++);
    if (replay(run, scene.bodies3d)) return scene.bodies3d;
    dem::World3d w(scene, decomposition(scene));
    if (!under_way_.empty()) restore(w);
    double paced_from = w.time();  // (a run continued counts its own part)
    auto paced_since = std::chrono::steady_clock::now();
    // With a checkpoint to feed or progress to tell, in slices of 2,000 steps, looking at the clock after
    // each: slicing a fixed-step run leaves its steps as they were.
    const double slice = save_ || progress_ ? 2000 * scene.accuracy.dt : duration;
    for (double before = -1; w.time() != before;) {  // until a slice takes no step: the run's end
      before = w.time();
      w.advance_to(std::min(duration, w.time() + slice));
      const auto now = std::chrono::steady_clock::now();
      if (progress_ && std::chrono::duration<double>(now - since_progress_).count() >= kProgressEvery &&
          w.time() + slice / 2 < duration) {  // (not for a run that has just ended)
        const double over = std::chrono::duration<double>(now - paced_since).count();
        progress_(w.time(), duration, time_left(over, paced_from, w.time(), duration));
        paced_from = w.time(), paced_since = now;
        since_progress_ = now;
      }
      bool due = save_ && std::chrono::duration<double>(now - since_save_).count() >= every_;
      if (w.distributed()) due = parallel::any_all(due);  // (saving a spread world is collective)
      if (!due) continue;
      std::map<std::string, SampleTable> world;
      for (SampleTable& t : w.save_state(kStageWorld)) world.emplace(t.name, std::move(t));
      save_(done_, world);
      since_save_ = now;
    }
    std::vector<double> rows;  // the finished run's rows, flat; a spread world has them on rank 0 only
    for (std::size_t i = 0; i < w.bodies().size() && (!w.distributed() || parallel::rank() == 0); ++i) {
      const std::vector<double> r = motion_row(run, w.bodies()[i]);
      rows.insert(rows.end(), r.begin(), r.end());
    }
    if (w.distributed()) parallel::broadcast(rows);
    std::vector<Body3Spec> out = scene.bodies3d;
    const std::size_t width = kStageRunColumns.size();
    for (std::size_t i = 0; i < out.size(); ++i) {
      done_.rows.emplace_back(rows.begin() + static_cast<long>(i * width),
                              rows.begin() + static_cast<long>((i + 1) * width));
      put_motion(done_.rows.back(), out[i]);
    }
    return out;
  }

  // The bodies after `duration`, then stopped: each stage of a build hands the next spheres at rest.
  std::vector<Body3Spec> settled(const Bed3dSpec& s, std::vector<Body3Spec> bodies, double k_n, double e,
                                 double duration) {
    return at_rest(left_alone(s, std::move(bodies), k_n, e, duration));
  }

 private:
  static InputError damaged(const std::string& why) {
    return InputError({}, "--checkpoint", "its stage under way " + why);
  }

  // A run the stage had finished before it was stopped: the bodies as it left them.
  bool replay(double run, std::vector<Body3Spec>& bodies) const {
    const auto first = std::find_if(done_.rows.begin(), done_.rows.end(),
                                    [run](const std::vector<double>& r) { return r[0] == run; });
    if (first == done_.rows.end()) return false;
    if (done_.rows.end() - first < static_cast<long>(bodies.size()))
      throw damaged(fmt::format("has fewer spheres after its run {} than the run starts with", run));
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const std::vector<double>& r = first[static_cast<long>(i)];
      if (r[0] != run)
        throw damaged(fmt::format("has fewer spheres after its run {} than it started with", run));
      put_motion(r, bodies[i]);
    }
    return true;
  }

  // Spread over the ranks when there are several and the scene is a bed of spheres the sphere kernel
  // runs (from kCellsFrom spheres: fewer run on one rank's general path, with other bits).
  dem::Decomposition decomposition(const Scene& scene) const {
    const bool spheres = std::all_of(scene.bodies3d.begin(), scene.bodies3d.end(),
                                     [](const Body3Spec& b) { return b.shape == Body3Spec::Shape::Sphere; });
    if (ranks_ != BedRanks::spread || parallel::size() == 1 || !spheres ||
        scene.bodies3d.size() < dem::World3d::kCellsFrom ||
        scene.accuracy.integrator != Integrator::VelocityVerlet)
      return {};
    return dem::Decomposition{true, dem::kBalanceEveryDefault, 1};
  }

  void restore(dem::World3d& w) {
    try {
      w.restore_state(under_way_, kStageWorld);
    } catch (const std::exception& e) {
      throw damaged(fmt::format("does not fit the stage ({})", e.what()));
    }
    under_way_.clear();
  }

  static constexpr double kProgressEvery = 60;  // s
  SampleTable done_;
  std::map<std::string, SampleTable> under_way_;
  double every_;
  Save save_;
  Progress progress_;
  BedRanks ranks_;
  std::size_t next_run_ = 0;
  std::chrono::steady_clock::time_point since_save_ = std::chrono::steady_clock::now();  // (the stage's)
  std::chrono::steady_clock::time_point since_progress_ = since_save_;
};

// The highest point of a grain.
double grain_top(const Body3Spec& g) {
  if (g.shape == Body3Spec::Shape::Sphere) return g.position.z() + g.radius;
  const Vec3 up = g.orientation.conjugate() * Vec3::UnitZ();  // (world up in the body's frame)
  return g.position.z() + (g.orientation * g.hull.vertices[g.hull.support(up)]).z();
}

bool holds_point(const Body3Spec& g, const Vec3& p) {
  const Vec3 d = p - g.position;
  if (d.squaredNorm() >= g.radius * g.radius) return false;  // (a polyhedron's bounding sphere)
  return g.shape == Body3Spec::Shape::Sphere || g.hull.contains(g.orientation.conjugate() * d);
}

// The exposed height of each 2 r x 2 r column in the middle 80 % of the box, and its 90th percentile.
double bed_top(const std::vector<Body3Spec>& b, const Bed3dSpec& s) {
  const double cell = 2 * s.radius;
  std::map<std::pair<long, long>, double> column;
  for (const Body3Spec& g : b) {
    const double x = g.position.x(), y = g.position.y();
    if (x < 0.1 * s.width || x > 0.9 * s.width || y < 0.1 * s.depth || y > 0.9 * s.depth) continue;
    double& h = column[{static_cast<long>(x / cell), static_cast<long>(y / cell)}];
    h = std::max(h, grain_top(g));
  }
  std::vector<double> h;
  for (const auto& [k, z] : column) h.push_back(z);
  if (h.empty()) throw std::runtime_error("3-D impact bed: no spheres in the middle of the box");
  std::sort(h.begin(), h.end());
  return h[static_cast<std::size_t>(0.9 * static_cast<double>(h.size() - 1))];
}

// Solid fraction on a 20^3 grid of points in the box [lo, hi].
double solid_fraction(const std::vector<Body3Spec>& b, const Vec3& lo, const Vec3& hi) {
  if ((hi - lo).minCoeff() <= 0) return kNaN;
  const int n = 20;
  int inside = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 p = lo + (hi - lo).cwiseProduct(Vec3(i + 0.5, j + 0.5, k + 0.5) / n);
        inside += std::any_of(b.begin(), b.end(), [&](const Body3Spec& s) { return holds_point(s, p); });
      }
  return double(inside) / (n * n * n);
}

// Per sphere: whether another rests on it (touches it with its centre higher by more than 30 % of the two
// radii: it sits on top, not beside). Neighbours through the engines' grid of cells, one largest diameter
// (and a margin) wide.
std::vector<char> carries_a_sphere(const std::vector<Body3Spec>& b) {
  double r_max = 0;
  for (const Body3Spec& s : b) r_max = std::max(r_max, s.radius);
  auto point = [&](std::size_t i) {
    return std::array<double, 3>{b[i].position.x(), b[i].position.y(), b[i].position.z()};
  };
  dem::CellGrid<3> grid;
  grid.build(b.size(), point, 2.02 * r_max);
  std::vector<char> carrying(b.size(), 0);
  std::size_t around[27];
  for (std::size_t i = 0; i < b.size(); ++i) {
    const int ns = grid.stencil(grid.coords(point(i)), around);
    for (int k = 0; k < ns && !carrying[i]; ++k)
      for (std::uint32_t m = grid.start()[around[k]]; m < grid.start()[around[k] + 1]; ++m) {
        const Body3Spec& o = b[grid.members()[m]];
        const double reach = b[i].radius + o.radius;
        if ((o.position - b[i].position).norm() < 1.01 * reach &&
            o.position.z() - b[i].position.z() > 0.3 * reach)
          carrying[i] = 1;
      }
  }
  return carrying;
}

struct Aim3 {
  Vec3 release, normal;  // normal: from the target's centre to the contact point
  Vec3 hit;              // the contact point on the target
  std::size_t target = 0;
};

// Where a sphere of radius `ri` moving along d = (cos a, 0, -sin a) through (x, y, top) first touches the
// bed (a ray cast of the inflated spheres from above); it is released `gap` before that.
Aim3 aim_at(const Bed3d& bed, double x, double y, double alpha, double ri, double gap) {
  const Vec3 d(std::cos(alpha), 0, -std::sin(alpha));
  const double lift = ri + 4 * bed.spec.radius;
  const Vec3 start(x - lift * d.x() / -d.z(), y, bed.top + lift);
  double best = std::numeric_limits<double>::infinity();
  Aim3 aim;
  const auto& b = bed.scene.bodies3d;
  for (std::size_t k = 0; k < b.size(); ++k) {
    const Vec3 o = start - b[k].position;
    const double reach = ri + b[k].radius, p = o.dot(d), disc = p * p - (o.squaredNorm() - reach * reach);
    if (disc < 0) continue;
    const double s = -p - std::sqrt(disc);
    if (s > 0 && s < best) best = s, aim.target = k, aim.normal = (o + s * d) / reach;
  }
  if (!std::isfinite(best)) throw std::runtime_error("3-D impact: the incident path misses the bed");
  aim.release = start + (best - gap) * d;
  aim.hit = b[aim.target].position + b[aim.target].radius * aim.normal;
  return aim;
}

Scene impact3d_scene(const Bed3d& bed, const ImpactCase& c, const Aim3& aim, const ImpactOptions& o) {
  Scene s = bed.scene;
  s.name = fmt::format("3-D impact CASE {}", c.name);
  s.duration = o.duration;
  s.materials.at(0).mu = c.mu;
  if (c.mu == 0) s.effects.set(Effect::friction, false);
  Body3Spec in;
  for (const Body3Spec& b : s.bodies3d) in.id = std::max(in.id, b.id + 1);
  const double rb = bed.spec.smallest_radius(), mb = sphere_mass(bed.spec.density, rb);
  in.radius = c.radius;
  in.mass =
      c.disc_mass_ratio ? mb * (c.radius / rb) * (c.radius / rb) : sphere_mass(bed.spec.density, c.radius);
  in.inertia = Mat3::Identity() * (0.4 * in.mass * c.radius * c.radius);  // (a uniform sphere of that mass)
  in.position = aim.release;
  in.velocity = Vec3(c.speed * std::cos(c.alpha_deg * kDeg), 0, -c.speed * std::sin(c.alpha_deg * kDeg));
  if (o.active_radius > 0) {
    // The grains beyond the active zone are held where they lie; those that no grain of the zone can
    // reach (a list's reach, two radii and the skin, plus as much again for the zone's grains to move)
    // are left out, so an impact costs the same on a bed of any size.
    const double reach = o.active_radius + 4.4 * bed.spec.largest_radius();
    std::vector<Body3Spec> near;
    for (Body3Spec& b : s.bodies3d) {
      const double d = (b.position - aim.hit).norm();
      if (d > reach) continue;
      b.held = d > o.active_radius;
      near.push_back(b);
    }
    s.bodies3d = std::move(near);
  }
  s.bodies3d.push_back(in);
  const double tc = std::min(contact_time(bed.spec.k_n, mb, mb), contact_time(bed.spec.k_n, mb, in.mass));
  s.accuracy.integrator = Integrator::VelocityVerlet;
  s.accuracy.dt = engine_capabilities(o.engine).soft_contacts ? tc / o.steps_per_contact : o.rigid_dt;
  return s;
}

}  // namespace

namespace {

// build_bed3d's stages, by the number done when each ends.
constexpr int kStiffeningSteps = 10, kMaxHolds = 4;
constexpr int kPoured = 1, kStiffened = kPoured + kStiffeningSteps, kDamped = kStiffened + 1,
              kRelaxed = kDamped + 1;

// As the 2-D beds are made (impact_bed.cpp): poured 100 x softer and less elastic (restitution 0.3), so it
// comes to rest in about a second at a tenth of the steps; then stiffened in ten critically damped steps
// of 10^0.2, so no grain is thrown; then relaxed with the bed's own material from rest.
constexpr double kSoftening = 100, kPourRestitution = 0.3;

// The bed as the pour, the stiffening and the damping see it: a dense bed without its friction.
Bed3dSpec while_packing(const Bed3dSpec& spec) {
  Bed3dSpec s = spec;
  if (spec.dense()) s.mu = 0;
  return s;
}

std::vector<Body3Spec> poured(const Bed3dSpec& spec, StageRuns& runs) {
  // (The pour's pitch follows the grains' bounding radii: an irregular grain's, with the default 20 %
  // irregularity and elongation rescaled to its sphere's volume, is up to about 1.7 times its sphere's
  // radius. 1.6 only lengthens the fall allowed before the settling; the second of settling after it
  // absorbs the difference.)
  const double pitch = 2.2 * spec.largest_radius() * (spec.polyhedra ? 1.6 : 1.0);
  const double per_layer =
      std::max(1.0, std::floor(spec.width / pitch)) * std::max(1.0, std::floor(spec.depth / pitch));
  const double column_top = pitch * std::ceil(spec.count / per_layer) + spec.radius;
  const double settle = std::sqrt(2 * column_top / 981.0) + spec.settle_time * spec.time_scale;
  const Scene pour =
      parse_scene(bed3d_text(spec, spec.k_n / kSoftening, kPourRestitution, settle, true), "3-D impact bed");
  // (The pour's own settling, run here so that it is checkpointed as any stage's runs are; the poured
  // assembly's velocity is zero, so the spheres come out at rest, as expanded_bodies3d gives them.)
  return at_rest(runs.run(dem::pour_settling_scene(pour), pour.assemblies[0].settle_time));
}

// The bed is left alone for an impact's 0.07 s, as every impact will leave it, and each sphere that moves
// more than 2.5 % of its radius (half the limit impacts-3d checks) is dealt with:
// - one that carries no other is a loose grain: a sphere in a pocket of the surface rolls to and fro
//   without loss (this contact law has no rolling resistance), so zeroing velocities does not put it at
//   rest. It is taken away, as loose grains are brushed off a prepared bed.
// - one that carries others is part of a bed still finding its place (a slow collapse near a wall, at a
//   few cm/s). Taking it away opens a hole the spheres above fall into: a 3,000-sphere sand bed lost 96 %
//   of its spheres in five passes, the 2,000-sphere thesis-sized one 99 %. The bed settles 0.2 s more,
//   critically damped, instead (a 700-sphere bed whose deep spheres slid 0.42 cm then moves 0.006 cm).
// Returns the log line.
std::string probe(const Bed3dSpec& spec, Bed3dBuild& b, StageRuns& runs) {
  const double ts = spec.time_scale;
  const std::vector<Body3Spec> moved = runs.settled(spec, b.bodies, spec.k_n, spec.restitution, 0.07 * ts);
  const std::vector<char> carrying = carries_a_sphere(b.bodies);
  std::vector<Body3Spec> kept;
  std::size_t deep_movers = 0;
  for (std::size_t i = 0; i < b.bodies.size(); ++i) {
    const bool moves = (moved[i].position - b.bodies[i].position).norm() > 0.025 * b.bodies[i].radius;
    if (!moves || carrying[i]) kept.push_back(b.bodies[i]);
    deep_movers += moves && carrying[i];
  }
  ++b.probes, b.deep_movers = deep_movers;
  const std::size_t taken = b.bodies.size() - kept.size();
  const std::string line = fmt::format("probe {}: {} loose spheres taken away, {} deep spheres still moving",
                                       b.probes, taken, deep_movers);
  if (taken == 0 && deep_movers == 0) {
    b.finished = true;
    return line;
  }
  b.removed += taken;
  for (std::size_t i = 0; i < kept.size(); ++i) kept[i].id = static_cast<std::int64_t>(i);
  b.bodies = runs.settled(spec, std::move(kept), spec.k_n, 0, (deep_movers ? 0.2 : 0.05) * ts);
  b.bodies = runs.settled(spec, std::move(b.bodies), spec.k_n, spec.restitution, 0.05 * ts);
  return line;
}

// When the probes run out with deep spheres still settling (a 20,000-sphere sand bed: 5-28 of them after
// each probe's settle), the bed is left alone as an impact will leave it, for an impact's duration, and
// judged by the limits the suite's bed-at-rest checks use. While a sphere breaks one, the bed is taken
// where the hold left it, stopped, and held again: no settle in between, since each settle set some
// deep sphere sliding anew, where held again that sand bed came to rest (6 spheres over a limit, then
// none). After kMaxHolds the bed is kept as the last hold found it, and its record says how many moved.
std::string hold(const Bed3dSpec& spec, Bed3dBuild& b, StageRuns& runs) {
  const AtRestLimits limits = at_rest_limits(spec);
  const std::vector<Body3Spec> moved =
      runs.left_alone(spec, b.bodies, spec.k_n, spec.restitution, 0.07 * spec.time_scale);
  std::size_t over = 0;
  for (std::size_t i = 0; i < moved.size(); ++i)
    over += limits.broken_by((moved[i].position - b.bodies[i].position).norm(), moved[i].velocity.norm());
  b.deep_movers = over;
  const int holds = b.stage - (kRelaxed + spec.max_probes);  // this one included
  const std::string line = fmt::format("hold {}: {} spheres over the at-rest limits", holds, over);
  if (over == 0 || holds == kMaxHolds) {
    b.finished = true;
    return line;
  }
  b.bodies = at_rest(moved);
  return line + ", held again from where they are";
}

// Runs the stage after b.stage; returns what it did, for the log.
std::string next_stage(const Bed3dSpec& spec, Bed3dBuild& b, StageRuns& runs) {
  const double ts = spec.time_scale;
  const int stage = b.stage++;
  if (stage == 0) {
    b.bodies = poured(while_packing(spec), runs);
    return "poured and settled soft";
  }
  if (stage < kStiffened) {
    const double k = spec.k_n / kSoftening * std::pow(kSoftening, stage / double(kStiffeningSteps));
    b.bodies = runs.settled(while_packing(spec), std::move(b.bodies), k, 0, 0.005 * ts);
    return fmt::format("stiffened to k_n {:.3g} dyn/cm", k);
  }
  // Critically damped at the bed's own stiffness until perched grains have found their places, then the
  // bed's own material from rest, as every impact will start.
  if (stage == kStiffened) {
    b.bodies = runs.settled(while_packing(spec), std::move(b.bodies), spec.k_n, 0, 0.1 * ts);
    return "damped";
  }
  if (stage == kDamped) {
    b.bodies = runs.settled(spec, std::move(b.bodies), spec.k_n, spec.restitution, 0.05 * ts);
    return "relaxed";
  }
  return static_cast<int>(b.probes) < spec.max_probes ? probe(spec, b, runs) : hold(spec, b, runs);
}

}  // namespace

Bed3d build_bed3d(const Bed3dSpec& spec, const std::function<void(const std::string&)>& log, Bed3dBuild from,
                  const std::function<void(const Bed3dBuild&)>& after_stage, double save_every,
                  BedRanks ranks) {
  check_preparation(spec.preparation, "preparation");
  Bed3dBuild b = std::move(from);
  while (!b.finished) {
    auto start = std::chrono::steady_clock::now();
    double seconds = b.seconds;  // (counted up to `start`)
    // The stage's start, for a checkpoint part-way through it (the stage moves its spheres on).
    Bed3dBuild at_start;
    StageRuns::Save save;
    if (after_stage) {
      at_start = b, at_start.runs_done = {}, at_start.run_under_way = {};
      save = [&](const SampleTable& done, const std::map<std::string, SampleTable>& world) {
        const auto now = std::chrono::steady_clock::now();
        seconds += std::chrono::duration<double>(now - start).count(), start = now;
        at_start.seconds = seconds, at_start.runs_done = done, at_start.run_under_way = world;
        after_stage(at_start);
      };
    }
    StageRuns::Progress progress;
    if (log)
      progress = [&](double done, double duration, double seconds_left) {
        const double elapsed =
            seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        log(
            fmt::format("bed of {} {}: stage {} under way, {:.4g} of {:.4g} s simulated, this run's end in "
                        "about {:.0f} min ({:.0f} s)",
                        spec.count, spec.polyhedra ? "irregular grains" : "spheres", b.stage, done, duration,
                        std::ceil(seconds_left / 60), elapsed));
      };
    StageRuns runs(b, save_every, std::move(save), ranks, std::move(progress));
    const std::string what = next_stage(spec, b, runs);
    b.seconds = seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (log)
      log(fmt::format("bed of {} {}: {} ({:.0f} s)", spec.count,
                      spec.polyhedra ? "irregular grains" : "spheres", what, b.seconds));
    if (after_stage) after_stage(b);
  }
  Bed3d bed = bed3d_from_bodies(spec, std::move(b.bodies));
  keep_build_record(bed, b);
  return bed;
}

AtRestLimits at_rest_limits(const Bed3dSpec& spec) {
  return {0.025 * 2 * spec.radius, 1.0 * spec.time_scale};
}

int build_holds(const Bed3d& bed) {
  return std::max(0, bed.build_stages - (kRelaxed + bed.spec.max_probes));
}

void keep_build_record(Bed3d& bed, const Bed3dBuild& b) {
  bed.removed = b.removed, bed.probes = b.probes, bed.deep_movers = b.deep_movers;
  bed.build_seconds = b.seconds, bed.build_stages = b.stage;
}

Bed3dBuild build_record(const Bed3d& bed) {
  Bed3dBuild b;
  b.stage = bed.build_stages, b.finished = true;
  b.removed = bed.removed, b.probes = bed.probes, b.deep_movers = bed.deep_movers,
  b.seconds = bed.build_seconds;
  return b;
}

std::string packing_text(const Bed3d& bed) {
  return std::isfinite(bed.packing_fraction)
             ? fmt::format("{:.3f}", bed.packing_fraction)
             : std::string(
                   "not measured (the bed is too thin for an interior 2 diameters from its walls, floor "
                   "and top)");
}

Bed3d bed3d_from_bodies(const Bed3dSpec& spec, std::vector<Body3Spec> bodies) {
  Bed3d bed;
  bed.spec = spec;
  bed.scene = parse_scene(bed3d_text(spec, spec.k_n, spec.restitution, 0.07 * spec.time_scale, false),
                          "3-D impact bed");
  bed.scene.bodies3d = std::move(bodies);
  bed.top = bed_top(bed.scene.bodies3d, spec);
  const double d = 2 * spec.radius;
  bed.packing_fraction = solid_fraction(bed.scene.bodies3d, Vec3(2 * d, 2 * d, 2 * d),
                                        Vec3(spec.width - 2 * d, spec.depth - 2 * d, bed.top - 2 * d));
  return bed;
}

BedHold hold_bed3d(const Bed3d& bed, const std::string& engine, double duration, double rigid_dt) {
  const Scene& s = bed.scene;
  const Frame f = bed_left_alone(s, engine, duration, rigid_dt);  // by id: the scene's order
  BedHold h;
  for (std::size_t i = 0; i < f.id.size(); ++i) {
    const Body3Spec& b = s.bodies3d[i];
    const Vec3 v(f.velocity[3 * i], f.velocity[3 * i + 1], f.velocity[3 * i + 2]);
    const Vec3 w(f.angular_velocity[3 * i], f.angular_velocity[3 * i + 1], f.angular_velocity[3 * i + 2]);
    const Vec3 x(f.position[3 * i], f.position[3 * i + 1], f.position[3 * i + 2]);
    h.displacement.push_back((x - b.position).norm());
    h.speed.push_back(v.norm());
    h.depth.push_back(bed.top - b.position.z());
    h.max_displacement = std::max(h.max_displacement, h.displacement.back());
    h.max_speed = std::max(h.max_speed, h.speed.back());
    h.kinetic_energy += 0.5 * b.mass * v.squaredNorm() + 0.5 * w.dot(b.inertia * w);
  }
  return h;
}

EngineBed settle_on_engine(const Bed3d& bed, const std::string& engine, double settle, int rounds,
                           double duration, double rigid_dt,
                           const std::function<void(const std::string&)>& log) {
  return settle_on_engine(EngineBed{bed, hold_bed3d(bed, engine, duration, rigid_dt), 0}, engine, settle,
                          rounds, duration, rigid_dt, log);
}

EngineBed settle_on_engine(EngineBed e, const std::string& engine, double settle, int rounds, double duration,
                           double rigid_dt, const std::function<void(const std::string&)>& log) {
  const Bed3dSpec spec = e.bed.spec;  // (a copy: e.bed is replaced below)
  const AtRestLimits limits = at_rest_limits(spec);
  auto say = [&](const EngineBed& now) {
    if (log)
      log(fmt::format(
          "{} after {} settles of {} s: the bed moves {:.3g} cm at {:.3g} cm/s in {} s, {} spheres over "
          "a limit",
          engine, now.settles, settle, now.hold.max_displacement, now.hold.max_speed, duration,
          grains_over(now.hold, limits)));
  };
  say(e);
  while (grains_over(e.hold, limits) > 0 && e.settles < rounds) {
    const Frame f = bed_left_alone(e.bed.scene, engine, settle, rigid_dt);  // by id: the scene's order
    std::vector<Body3Spec> b = e.bed.scene.bodies3d;
    for (std::size_t i = 0; i < b.size(); ++i) {
      b[i].position = Vec3(f.position[3 * i], f.position[3 * i + 1], f.position[3 * i + 2]);
      b[i].orientation = Quat(f.orientation[4 * i], f.orientation[4 * i + 1], f.orientation[4 * i + 2],
                              f.orientation[4 * i + 3]);
      b[i].velocity = Vec3::Zero(), b[i].spin = Vec3::Zero();
    }
    e.bed = bed3d_from_bodies(spec, std::move(b));
    ++e.settles;
    e.hold = hold_bed3d(e.bed, engine, duration, rigid_dt);
    say(e);
  }
  return e;
}

std::size_t grains_over(const BedHold& h, const AtRestLimits& limits) {
  std::size_t over = 0;
  for (std::size_t i = 0; i < h.speed.size(); ++i) over += limits.broken_by(h.displacement[i], h.speed[i]);
  return over;
}

std::string where_the_bed_moved(const BedHold& h, const AtRestLimits& limits) {
  if (h.displacement.empty()) return "no spheres";
  const auto most = std::max_element(h.displacement.begin(), h.displacement.end()) - h.displacement.begin();
  return fmt::format(
      "{} spheres over a limit; the one that moved most ({:.3g} cm) sits {:.3g} cm below the top",
      grains_over(h, limits), h.displacement[most], h.depth[most]);
}

Impact3dResult run_impact3d(const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, std::size_t run,
                            const ImpactOptions& o) {
  if (c.bed != bed.spec.preparation)
    throw std::invalid_argument(fmt::format("3-D impact: CASE {} is for a {} bed, this one is {}", c.name,
                                            c.bed, bed.spec.preparation));
  const auto start = std::chrono::steady_clock::now();
  Rng rng(seed, run);
  const Bed3dSpec& s = bed.spec;
  const double x = 0.5 * s.width + (rng.uniform() - 0.5) * o.window * s.width;
  const double y = 0.5 * s.depth + (rng.uniform() - 0.5) * o.window * s.depth;
  const Aim3 aim = aim_at(bed, x, y, c.alpha_deg * kDeg, c.radius, 0.01 * c.radius);
  const Scene scene = impact3d_scene(bed, c, aim, o);
  const std::vector<Body3Spec>& b = bed.scene.bodies3d;
  Impact3dResult r;
  const Vec3& hit = aim.hit;
  r.x_impact = hit.x(), r.y_impact = hit.y(), r.z_impact = hit.z();
  r.incident_speed = c.speed, r.alpha_deg = c.alpha_deg;
  r.incident_mass = scene.bodies3d.back().mass, r.bed_mass = b[aim.target].mass;
  r.g = -scene.gravity3d.z();

  auto engine = make_engine(o.engine, scene);
  // The frame is by id: the bed's grains in the scene (all of them, or an active zone's), then the
  // incident one. bed_index maps a frame row to the grain's place in the bed.
  const std::size_t n = scene.bodies3d.size() - 1;
  std::vector<std::size_t> bed_index(n);
  for (std::size_t k = 0, i = 0; k < n; ++k) {
    while (i < b.size() && b[i].id != scene.bodies3d[k].id) ++i;  // (both in the bed's order)
    if (i == b.size()) throw std::logic_error("3-D impact: the scene's grains are not in the bed's order");
    bed_index[k] = i;
  }
  const double z_eject = bed.top + 2 * s.radius;
  std::vector<char> gone(n, 0);
  double z_left = aim.release.z();
  for (double t = 0; t < o.duration;) {
    t = std::min(o.duration, t + o.check_interval);
    engine->advance_to(t);
    const Frame f = engine->frame();
    for (std::size_t k = 0; k < n; ++k) {
      const double z = f.position[3 * k + 2], vz = f.velocity[3 * k + 2];
      if (gone[k] || z <= z_eject || vz <= 0) continue;
      gone[k] = 1;
      const Body3Spec& at = b[bed_index[k]];
      const Vec3 from = at.position - hit;
      const double vz_launch = std::sqrt(vz * vz + 2 * r.g * std::max(0.0, z - at.position.z()));
      r.ejecta.push_back({f.id[k], at.mass, from.x(), from.y(), from.z(), f.velocity[3 * k],
                          f.velocity[3 * k + 1], vz, vz_launch, t});
    }
    if (r.rebounded) continue;
    const Vec3 p(f.position[3 * n], f.position[3 * n + 1], f.position[3 * n + 2]);
    for (std::size_t i = 0; i < n; ++i)
      if ((p - Vec3(f.position[3 * i], f.position[3 * i + 1], f.position[3 * i + 2])).squaredNorm() <
          std::pow(c.radius + f.radius[i], 2)) {
        z_left = p.z();
        break;
      }
    const double vz = f.velocity[3 * n + 2];
    if (p.z() > z_eject && vz > 0) {
      r.rebounded = true;
      r.vx = f.velocity[3 * n], r.vy = f.velocity[3 * n + 1];
      r.vz = std::sqrt(vz * vz + 2 * r.g * std::max(0.0, p.z() - z_left));
    }
  }
  const auto d = engine->diagnostics();
  if (d.count("steps")) r.steps = d.at("steps");
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  record_impact(scene, o);
  return r;
}

Impact3dSummary summarize_impacts3d(const std::vector<Impact3dResult>& results) {
  std::map<std::string, std::vector<double>> v;
  Impact3dSummary s;
  std::vector<double> wall, steps;
  for (const Impact3dResult& r : results) {
    const double a = r.alpha_deg * kDeg, speed = r.incident_speed;
    const double vx_in = speed * std::cos(a), vz_in = speed * std::sin(a);
    auto rebound = [&](double x) { return r.rebounded ? x : kNaN; };
    v["rebounded"].push_back(r.rebounded ? 1 : 0);
    v["eps_ix"].push_back(rebound(r.vx / vx_in));
    v["eps_iy"].push_back(rebound(r.vz / vz_in));
    v["eps_iz"].push_back(rebound(r.vy / speed));
    v["eps_i"].push_back(rebound(std::sqrt(r.vx * r.vx + r.vy * r.vy + r.vz * r.vz) / speed));
    v["theta_i"].push_back(rebound(std::atan2(std::hypot(r.vx, r.vy), r.vz) / kDeg));
    double reptation = 0, energy = 0;
    for (const Ejectum3d& e : r.ejecta) {
      const double azimuth = std::atan2(e.vy, e.vx);
      v["ej_speed"].push_back(std::sqrt(e.vx * e.vx + e.vy * e.vy + e.vz * e.vz));
      v["ej_vy"].push_back(e.vz);
      v["ej_angle"].push_back(std::atan2(e.vx, e.vz) / kDeg);
      v["ej_tilt"].push_back(std::atan2(std::hypot(e.vx, e.vy), e.vz) / kDeg);
      v["ej_azimuth"].push_back(azimuth / kDeg);
      v["ej_sideways"].push_back(std::abs(std::sin(azimuth)));
      v["ej_sin_azimuth"].push_back(std::sin(azimuth));
      v["ej_backward"].push_back(e.vx < 0 ? 1 : 0);
      v["origin_r"].push_back(std::hypot(e.x0, e.y0));
      reptation += 2 * e.vx * e.vz / r.g;
      energy += 0.5 * e.mass * (e.vx * e.vx + e.vy * e.vy + e.vz_launch * e.vz_launch);
      ++s.ejecta;
    }
    v["ejected"].push_back(static_cast<double>(r.ejecta.size()));
    v["reptation"].push_back(reptation);
    v["ej_energy"].push_back(energy / (0.5 * r.incident_mass * speed * speed));
    s.rebounds += r.rebounded;
    steps.push_back(r.steps);
    wall.push_back(r.wall_seconds);
  }
  s.impacts = results.size();
  const RunCost cost = run_cost(wall, steps);
  s.median_wall_seconds = cost.median_wall_seconds, s.mean_steps = cost.mean_steps;
  for (const auto& [k, x] : v) s.q[k] = mean_interval(x);
  return s;
}

namespace {
constexpr std::size_t kHead3 = kImpact3dHead, kPer3 = kImpact3dPerEjectum;
}  // namespace

std::vector<double> impact3d_row(const Impact3dResult& r) {
  std::vector<double> row{
      r.x_impact, r.y_impact,       r.z_impact,  r.rebounded ? 1.0 : 0.0, r.vx,       r.vy,
      r.vz,       r.incident_speed, r.alpha_deg, r.incident_mass,         r.bed_mass, r.g,
      r.steps,    r.wall_seconds};
  row.resize(kHead3 + kMaxEjecta * kPer3, kNaN);
  for (std::size_t k = 0; k < std::min(r.ejecta.size(), kMaxEjecta); ++k) {
    const Ejectum3d& e = r.ejecta[k];
    const double q[kPer3] = {double(e.id), e.mass, e.x0, e.y0, e.z0, e.vx, e.vy, e.vz, e.vz_launch, e.time};
    std::copy(q, q + kPer3, row.begin() + static_cast<long>(kHead3 + k * kPer3));
  }
  return row;
}

Impact3dResult impact3d_from_row(const std::vector<double>& w) {
  Impact3dResult r;
  r.x_impact = w[0], r.y_impact = w[1], r.z_impact = w[2], r.rebounded = w[3] != 0;
  r.vx = w[4], r.vy = w[5], r.vz = w[6], r.incident_speed = w[7], r.alpha_deg = w[8];
  r.incident_mass = w[9], r.bed_mass = w[10], r.g = w[11], r.steps = w[12], r.wall_seconds = w[13];
  for (std::size_t k = 0; k < kMaxEjecta; ++k) {
    const double* q = w.data() + kHead3 + k * kPer3;
    if (std::isnan(q[0])) break;
    r.ejecta.push_back(
        {static_cast<std::int64_t>(q[0]), q[1], q[2], q[3], q[4], q[5], q[6], q[7], q[8], q[9]});
  }
  return r;
}

namespace {
// Impact `index(k)` for k < count, on bed_of(index(k)), dealt out over the ranks.
std::vector<Impact3dResult> impact3d_rows(const std::function<const Bed3d&(std::size_t)>& bed_of,
                                          const ImpactCase& c, std::uint64_t seed, std::size_t count,
                                          const std::function<std::size_t(std::size_t)>& index,
                                          const ImpactOptions& o,
                                          const std::function<void(std::size_t, std::size_t)>& progress) {
  const auto rows = run_ensemble(
      count, kHead3 + kMaxEjecta * kPer3,
      [&](std::size_t k) { return impact3d_row(run_impact3d(bed_of(index(k)), c, seed, index(k), o)); },
      progress);
  std::vector<Impact3dResult> out;
  for (const auto& row : rows) out.push_back(impact3d_from_row(row));
  return out;
}
std::size_t same(std::size_t i) {
  return i;
}
}  // namespace

std::vector<Impact3dResult> run_impact3d_ensemble(
    const std::vector<Bed3d>& beds, const ImpactCase& c, std::uint64_t seed, std::size_t runs,
    const ImpactOptions& o, const std::function<void(std::size_t, std::size_t)>& progress) {
  return impact3d_rows([&](std::size_t i) -> const Bed3d& { return beds[i % beds.size()]; }, c, seed, runs,
                       same, o, progress);
}

std::vector<Impact3dResult> run_impact3d_ensemble(
    const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, std::size_t runs, const ImpactOptions& o,
    const std::function<void(std::size_t, std::size_t)>& progress) {
  return impact3d_rows([&](std::size_t) -> const Bed3d& { return bed; }, c, seed, runs, same, o, progress);
}

std::vector<Impact3dResult> run_impact3d_indices(
    const Bed3d& bed, const ImpactCase& c, std::uint64_t seed, const std::vector<std::size_t>& indices,
    const ImpactOptions& o, const std::function<void(std::size_t, std::size_t)>& progress) {
  return impact3d_rows([&](std::size_t) -> const Bed3d& { return bed; }, c, seed, indices.size(),
                       [&](std::size_t k) { return indices[k]; }, o, progress);
}

}  // namespace grainlab::validation
