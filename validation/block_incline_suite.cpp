// Suite `block-incline`: the thesis's 5 x 5 x 1 cm block rolling down a 40 degree incline (Figs 2.9-2.10)
// on the 3-D engines: how its rotational energy shares out over the body axes with distance down the
// plane, and whether rotation stays about the axis of largest inertia.
#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cmath>

#include "engine.hpp"
#include "ensemble.hpp"
#include "polyhedron.hpp"
#include "rng.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

constexpr double kIncline = 40.0, kDuration = 1.5, kSample = 0.01;
constexpr std::uint64_t kSeed = 1987;
constexpr int kBins = 10;
constexpr std::size_t kColumns = 5;
// A block is rolling while rotation holds at least this share of its kinetic energy (a wheel-like
// roll of this block holds about 0.4; a block that has fallen flat and slides holds next to none).
constexpr double kRollingShare = 0.1;
// The material and the start of the roll; the report's text is written from these.
constexpr double kMu = 1.0, kRestitution = 0.5, kSpin = 20.0, kSpeed = 50.0;

// Body x is the thin axis (perpendicular to the large faces: largest moment of inertia). The block stands
// on a 5 x 1 edge with body x across the slope (world y), rolling downslope (+x) like a wheel, perturbed
// by a random tilt of up to 0.1 rad and spin of up to 2 rad/s about each axis.
std::string block_scene(const Quat& q, const Vec3& w, const Vec3& v, double incline_deg = kIncline) {
  const double th = incline_deg * M_PI / 180;
  return fmt::format(R"toml(
[scene]
dimension = 3
name = "5 x 5 x 1 cm block on a 40 degree incline"
duration = {duration}
gravity = [{gx:.17g}, 0.0, {gz:.17g}]
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 5e-6
[materials.rock]
k_n = 1e9
restitution = {e}
k_s = 1e9
mu = {mu}
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[[bodies]]
shape = "box"
size = [1.0, 5.0, 5.0]
density = 2.0
position = [0.0, 0.0, 2.6]
orientation = [{qw:.17g}, {qx:.17g}, {qy:.17g}, {qz:.17g}]
velocity = [{vx:.17g}, {vy:.17g}, {vz:.17g}]
spin = [{wx:.17g}, {wy:.17g}, {wz:.17g}]
)toml",
                     fmt::arg("duration", kDuration), fmt::arg("e", kRestitution), fmt::arg("mu", kMu),
                     fmt::arg("gx", kG * std::sin(th)), fmt::arg("gz", -kG * std::cos(th)),
                     fmt::arg("qw", q.w()), fmt::arg("qx", q.x()), fmt::arg("qy", q.y()),
                     fmt::arg("qz", q.z()), fmt::arg("vx", v.x()), fmt::arg("vy", v.y()),
                     fmt::arg("vz", v.z()), fmt::arg("wx", w.x()), fmt::arg("wy", w.y()),
                     fmt::arg("wz", w.z()));
}

std::vector<std::string> accuracy_for(const std::string& engine) {
  if (engine_capabilities(engine).soft_contacts)
    return {"accuracy.dt=5e-6"};  // 1e9 dyn/cm on 50 g: 40 steps per contact
  return {"accuracy.dt=5e-4"};
}

// One roll: samples of (distance down the plane, fraction of rotational energy about body x, y, z,
// share of the kinetic energy that is rotational).
std::vector<double> roll(const std::string& engine, std::size_t index) {
  Rng rng(kSeed, index);
  const Quat wheel(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));  // body x -> world y
  const Quat tilt(Eigen::AngleAxisd(rng.uniform(-0.1, 0.1), Vec3::UnitX()) *
                  Eigen::AngleAxisd(rng.uniform(-0.1, 0.1), Vec3::UnitZ()));
  const Vec3 spin = Vec3(0, kSpin, 0) + Vec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
  const Scene scene = parse_scene(block_scene(tilt * wheel, spin, Vec3(kSpeed, 0, 0)),
                                  "<block on an incline>", accuracy_for(engine));
  auto e = make_engine(engine, scene);
  const Mat3& inertia = scene.bodies3d[0].inertia;
  const double mass = scene.bodies3d[0].mass;
  std::vector<double> out;  // flattened rows of kColumns
  for (double t = kSample; t <= kDuration + 1e-9; t += kSample) {
    e->advance_to(t);
    const Frame fr = e->frame();
    const Quat q(fr.orientation[0], fr.orientation[1], fr.orientation[2], fr.orientation[3]);
    const Vec3 wb =
        q.conjugate() * Vec3(fr.angular_velocity[0], fr.angular_velocity[1], fr.angular_velocity[2]);
    std::array<double, 3> part{};
    double total = 0;
    for (int k = 0; k < 3; ++k)
      total += part[k] = 0.5 * inertia(k, k) * wb[k] * wb[k];  // body axes principal
    const double translational =
        0.5 * mass * Vec3(fr.velocity[0], fr.velocity[1], fr.velocity[2]).squaredNorm();
    out.push_back(fr.position[0]);
    for (int k = 0; k < 3; ++k) out.push_back(total > 0 ? part[k] / total : 0);
    out.push_back(total + translational > 0 ? total / (total + translational) : 0);
  }
  return out;
}

// The block spinning freely (no gravity, far from the plane) about body x at kSpin with 1.5 and -1 rad/s
// about y and z, for 2 s: |relative change| of the rotational energy about x. Torque-free rotation about
// the axis of largest inertia keeps it constant, so this separates an engine's free rotation from its
// contacts.
double free_rotation_drift(const std::string& engine) {
  const Scene scene = parse_scene(
      block_scene(Quat::Identity(), Vec3(kSpin, 1.5, -1.0), Vec3::Zero()), "<free rotation>",
      {"scene.gravity=[0.0, 0.0, 0.0]", "bodies.0.position=[0.0, 0.0, 100.0]", "scene.duration=2.0"});
  auto e = make_engine(engine, scene);
  const double ix = scene.bodies3d[0].inertia(0, 0);
  auto about_x = [&](const Frame& f) {
    const Quat q(f.orientation[0], f.orientation[1], f.orientation[2], f.orientation[3]);
    const Vec3 wb = q.conjugate() * Vec3(f.angular_velocity[0], f.angular_velocity[1], f.angular_velocity[2]);
    return 0.5 * ix * wb.x() * wb.x();
  };
  const double e0 = about_x(e->frame());
  e->advance_to(2.0);
  return std::abs(about_x(e->frame()) / e0 - 1);
}

struct EngineResult {
  std::string engine;
  std::vector<std::vector<double>> rolls;  // per roll: flattened (distance, fx, fy, fz) samples
  double seconds = 0;
};

// Every engine's rolls, timed.
std::vector<EngineResult> roll_on_every_engine(const SuiteOptions& o, std::size_t rolls,
                                               std::size_t samples) {
  std::vector<EngineResult> results;
  for (const std::string& eng : engines_for_dimension(3)) {
    const auto start = std::chrono::steady_clock::now();
    EngineResult res{eng,
                     run_ensemble(
                         rolls, kColumns * samples, [&](std::size_t i) { return roll(eng, i); }, o.progress),
                     0};
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.log) o.log(fmt::format("block on an incline on {}: {} rolls ({:.1f} s)", eng, rolls, res.seconds));
    results.push_back(std::move(res));
  }
  return results;
}

// One engine's rotational energy while the block rolls (rotation >= kRollingShare of its kinetic energy):
// the fractions about each body axis, weighted by the rotational share, and the fraction about x binned by
// distance down the plane up to `reach`.
struct RollingShares {
  std::array<double, 3> part{};
  std::size_t still_rolling = 0;  // rolls still rolling at the end
  std::array<double, kBins> bin_sum{}, bin_n{};
};

RollingShares rolling_shares(const EngineResult& res, std::size_t samples, double reach) {
  RollingShares out;
  double weight = 0;
  for (const auto& row : res.rolls) {
    out.still_rolling += row[kColumns * (samples - 1) + 4] >= kRollingShare;
    for (std::size_t s = 0; s < samples; ++s) {
      const double* x = &row[kColumns * s];
      if (x[4] < kRollingShare) continue;
      for (int k = 0; k < 3; ++k) out.part[k] += x[4] * x[1 + k];
      weight += x[4];
      const int b = static_cast<int>(x[0] / reach * kBins);
      if (b >= 0 && b < kBins) out.bin_sum[b] += x[1], out.bin_n[b] += 1;
    }
  }
  for (double& p : out.part) p = weight > 0 ? p / weight : 0;
  return out;
}

// The engine's samples for the report's results.h5: one row per roll and sample time.
SampleTable roll_samples(const EngineResult& res, std::size_t samples) {
  std::vector<std::vector<double>> table;
  for (std::size_t i = 0; i < res.rolls.size(); ++i)
    for (std::size_t k = 0; k < samples; ++k) {
      const double* x = &res.rolls[i][kColumns * k];
      table.push_back({double(i), (k + 1) * kSample, x[0], x[1], x[2], x[3], x[4]});
    }
  return {"block_incline/" + res.engine,
          "one row per sample: roll, time (s), distance down the plane (cm), fraction of rotational "
          "energy about body x, y, z, rotational share of the kinetic energy",
          {"roll", "time_s", "distance_cm", "fraction_x", "fraction_y", "fraction_z", "rotational_share"},
          std::move(table)};
}

// The check that most rotational energy stays about x; Bullet's failure is its contact impulses' (its free
// rotation is right), stated with the least any engine before it kept (`others`).
void expect_rotation_about_x(Report& r, const std::string& engine, double fraction_x,
                             const std::vector<double>& others) {
  Check& c = r.expect_below(
      "block-incline/rotation-stays-about-largest-axis", engine, -fraction_x, -0.5,
      "minus the fraction of rotational energy about body x while the block rolls (rotation >= 10 % "
      "of its kinetic energy): the thesis's 'most of the rotational energy remains in rotation "
      "around the x body axis' (fraction above 1/2)");
  if (engine != "bullet") return;
  double least = 1;  // the least any other engine keeps about x
  for (const double other : others) least = std::min(least, other);
  c.known_limitation(fmt::format(
      "Bullet's corner impacts on the plane feed rotation into the block's y and z axes. Its free "
      "rotation "
      "is right (torque-free at {} rad/s, the energy about x changes by {:.1e} in 2 s), so the spreading "
      "comes from its contact impulses; the other engines keep at least {:.2f} about x",
      kSpin, free_rotation_drift("bullet"), least));
}

}  // namespace

void run_block_incline_suite(Report& r, const SuiteOptions& o) {
  const std::size_t rolls = o.quick ? 8 : 48;
  const std::size_t samples = static_cast<std::size_t>(std::lround(kDuration / kSample));
  const std::vector<EngineResult> results = roll_on_every_engine(o, rolls, samples);
  // The block's inertia as the scene reader makes it (body axes are principal).
  const Mat3 inertia = parse_scene(block_scene(Quat::Identity(), Vec3::Zero(), Vec3::Zero()), "<block>", {})
                           .bodies3d[0]
                           .inertia;
  // Binned by distance down the plane, over the distance every roll reached.
  double reach = HUGE_VAL;
  for (const auto& res : results)
    for (const auto& row : res.rolls) reach = std::min(reach, row[kColumns * (samples - 1)]);
  std::string md = fmt::format(
      "## Block on an incline (suite `block-incline`)\n\n"
      "The thesis's 5 x 5 x 1 cm block (density 2) on a {} deg incline (g = 981 cm/s^2, restitution {}, "
      "mu {}), started rolling like a wheel about its thin body x axis (largest moment of inertia: "
      "I_x = {:.0f}, I_y = {:.0f}, I_z = {:.0f} g cm^2) at {} rad/s and {} cm/s, tilted up to 0.1 rad and "
      "with "
      "up to 2 rad/s about each axis at random (Rng({}, roll)); {} rolls of {} s per engine. Fraction of the "
      "rotational energy about each body axis, averaged over rolls in {} bins of distance down the plane "
      "(to {:.0f} cm, the distance every roll reached), as in Fig. 2.10.\n\n",
      kIncline, kRestitution, kMu, inertia(0, 0), inertia(1, 1), inertia(2, 2), kSpin, kSpeed, kSeed, rolls,
      kDuration, kBins, reach);
  md +=
      "| engine | rolls still rolling at the end | energy about x while rolling | about y | about z | "
      "time |\n|---|---|---|---|---|---|\n";
  PlotSpec plot{"block_incline.png",
                "5 x 5 x 1 block on a 40 deg incline: rotational energy about body x",
                "distance down the plane (cm)",
                "fraction of rotational energy about x (rolling samples)",
                false,
                {}};
  std::vector<double> fractions_x;  // of the engines before Bullet (catalog order: native, ODE, Bullet)
  for (const auto& res : results) {
    const RollingShares sh = rolling_shares(res, samples, reach);
    const Proportion rolling = wilson_interval(sh.still_rolling, res.rolls.size());
    md += fmt::format("| {} | {} of {} ({:.2f} +- {:.2f}) | {:.3f} | {:.3f} | {:.3f} | {:.0f} s |\n",
                      res.engine, sh.still_rolling, res.rolls.size(), rolling.p, rolling.half_width(),
                      sh.part[0], sh.part[1], sh.part[2], res.seconds);
    expect_rotation_about_x(r, res.engine, sh.part[0], fractions_x);
    if (res.engine != "bullet") fractions_x.push_back(sh.part[0]);
    PlotSpec::Series series{res.engine, "line", {}, {}, {}};
    for (int b = 0; b < kBins; ++b)
      if (sh.bin_n[b] > 0)
        series.x.push_back((b + 0.5) * reach / kBins), series.y.push_back(sh.bin_sum[b] / sh.bin_n[b]);
    plot.series.push_back(series);
    r.samples.push_back(roll_samples(res, samples));
  }
  r.plots.push_back(plot);
  md += "\n![block on an incline](block_incline.png)\n\n";
  r.markdown.push_back(md);
}

}  // namespace grainlab::validation
