// Suite `single-body`, 3-D part: the analytic single-body checks of issue #3 on every engine that runs
// 3-D scenes (native, Bullet, ODE): free flight, a sphere's bounce, a block sliding and sticking and a
// sphere rolling on an incline (a floor with gravity tilted by theta), torque-free rotation of an
// asymmetric box (conservation, and the intermediate-axis instability), and a loaded cube's rest heights.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

Vec3 position(const Frame& f) {
  return {f.position[0], f.position[1], f.position[2]};
}
Quat orientation(const Frame& f) {
  return {f.orientation[0], f.orientation[1], f.orientation[2], f.orientation[3]};
}
Vec3 angular_velocity(const Frame& f) {
  return {f.angular_velocity[0], f.angular_velocity[1], f.angular_velocity[2]};
}

const char* kMaterial = R"toml([materials.m]
k_n = 1e7
restitution = 0.2
k_s = 1e7
damping_s = 3000
mu = {mu}
[[walls]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0])toml";

void free_flight(Report& r, const std::string& eng) {
  const std::string toml = R"toml(
[scene]
dimension = 3
duration = 1.0
effects = ["gravity"]
[accuracy]
integrator = "verlet"
[[bodies]]
shape = "sphere"
radius = 1.0
density = 2.0
position = [0.0, 0.0, 0.0]
velocity = [100.0, 50.0, 300.0]
)toml";
  const double exact = 300.0 - 0.5 * kG;
  double err[2];
  const double dts[2] = {1e-3, 5e-4};
  for (int k = 0; k < 2; ++k) {
    auto e = engine_for(eng, toml, {fmt::format("accuracy.dt={}", dts[k])});
    e->advance_to(1.0);
    const Vec3 x = position(e->frame());
    err[k] = (x - Vec3(100, 50, exact)).norm();
  }
  const double order = err[1] > 0 ? std::log2(err[0] / err[1]) : INFINITY;
  r.expect_below("3d/free-flight/position-error", eng, err[0], kG * dts[0],
                 fmt::format("sphere, |x(1 s) - parabola| at dt = 1e-3 s, below g dt; order in dt: {}",
                             std::isfinite(order) ? fmt::format("{:.2f}", order) : std::string("exact")));
}

struct Slide {
  double acceleration = 0, distance = 0;
};

// A body on a frictional floor (z = 0) with gravity tilted by theta towards +x, integrated by Verlet.
std::string on_floor_scene(double theta_deg, double mu, const std::string& body) {
  const double th = theta_deg * M_PI / 180;
  return fmt::format(R"toml(
[scene]
dimension = 3
duration = 1.0
gravity = [{gx}, 0.0, {gz}]
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-5
{material}
{body}
)toml",
                     fmt::arg("gx", kG * std::sin(th)), fmt::arg("gz", -kG * std::cos(th)),
                     fmt::arg("material", fmt::format(fmt::runtime(kMaterial), fmt::arg("mu", mu))),
                     fmt::arg("body", body));
}

// Downslope (x) acceleration between 0.2 and 0.6 s, and the distance moved.
Slide incline(const std::string& eng, const std::string& body, double theta_deg, double mu,
              const std::vector<std::string>& sets = {}) {
  const std::string toml = on_floor_scene(theta_deg, mu, body);
  auto e = engine_for(eng, toml, sets);
  e->advance_to(0.2);
  const Frame a = e->frame();
  e->advance_to(0.6);
  const Frame b = e->frame();
  return {(b.velocity[0] - a.velocity[0]) / 0.4, (position(b) - position(a)).norm()};
}

const char* kBlock = R"toml([[bodies]]
shape = "box"
size = [5.0, 5.0, 1.0]
density = 2.0
position = [0.0, 0.0, 0.4998])toml";
const char* kSphere = R"toml([[bodies]]
shape = "sphere"
radius = 1.0
density = 2.0
position = [0.0, 0.0, 0.9998])toml";

// Torque-free rotation of a 1 x 2 x 3 cm box started spinning about body axis `axis` (0: x, largest
// moment; 1: y, intermediate; 2: z, smallest) with a 1e-3 perturbation on the other two. Returns the
// relative drift of energy and angular momentum over 10 s and the smallest ratio of the spin axis's
// body-frame angular velocity to its start value (negative: the body flipped).
struct Rotation {
  double energy_drift = 0, momentum_drift = 0, min_ratio = 1;
};
Rotation torque_free(const std::string& eng, int axis, const std::vector<std::string>& sets) {
  Vec3 w = Vec3::Constant(5e-3);
  w[axis] = 5.0;
  const std::string toml = fmt::format(R"toml(
[scene]
dimension = 3
duration = 10.0
effects = ["rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-4
[[bodies]]
shape = "box"
size = [1.0, 2.0, 3.0]
density = 1.0
position = [0.0, 0.0, 0.0]
spin = [{}, {}, {}]
)toml",
                                       w.x(), w.y(), w.z());
  auto e = engine_for(eng, toml, sets);
  const Mat3 I = Vec3(13.0, 10.0, 5.0).asDiagonal() * (6.0 / 12.0);  // m (b^2 + c^2) / 12, m = 6 g
  auto state = [&](const Frame& f, double& energy, Vec3& L) {
    const Mat3 R = orientation(f).toRotationMatrix();
    const Vec3 wb = R.transpose() * angular_velocity(f);
    energy = 0.5 * wb.dot(I * wb);
    L = R * (I * wb);
    return wb;
  };
  double e0, e1;
  Vec3 L0, L1;
  state(e->frame(), e0, L0);
  Rotation out;
  for (int k = 1; k <= 400; ++k) {
    e->advance_to(k * 0.025);
    const Vec3 wb = state(e->frame(), e1, L1);
    out.energy_drift = std::max(out.energy_drift, std::abs(e1 - e0) / e0);
    out.momentum_drift = std::max(out.momentum_drift, (L1 - L0).norm() / L0.norm());
    out.min_ratio = std::min(out.min_ratio, wb[axis] / w[axis]);
  }
  return out;
}

// Centre-of-mass height of a 2 cm cube with its centre of mass at 0.2 (1, 1, 1) from the centre, left
// on a floor with the face whose outward body normal is `down` facing down.
double cube_rest_height(const std::string& eng, const Vec3& down) {
  const Quat q = Quat::FromTwoVectors(down, Vec3(0, 0, -1));
  const Vec3 com(0.2, 0.2, 0.2);
  const double expected = 1.0 - down.dot(com);
  const std::string toml =
      on_floor_scene(0.0, 0.8,
                     fmt::format(R"toml([[bodies]]
shape = "box"
size = [2.0, 2.0, 2.0]
center_of_mass = [0.2, 0.2, 0.2]
density = 2.0
position = [0.0, 0.0, {z}]
orientation = [{w}, {x}, {y}, {qz}])toml",
                                 fmt::arg("z", expected + 0.002), fmt::arg("w", q.w()), fmt::arg("x", q.x()),
                                 fmt::arg("y", q.y()), fmt::arg("qz", q.z())));
  auto e = engine_for(eng, toml);
  e->advance_to(0.5);
  return e->frame().position[2];
}

}  // namespace

void single_body_3d_checks(Report& r, const std::string& eng, std::string& md) {
  free_flight(r, eng);
  const double e1 = bounce_restitution(eng, 1.0, "restitution = 0.7", 3);
  for (double v : {1.0, 50.0, 500.0})
    r.expect_near(fmt::format("3d/bounce/restitution/v={}", v), eng,
                  v == 1.0 ? e1 : bounce_restitution(eng, v, "restitution = 0.7", 3), 0.7, 0.007,
                  "sphere on a plane; the scene's restitution within 1 %");
  const double a_slide = kG * (std::sin(M_PI / 6) - 0.3 * std::cos(M_PI / 6));
  const Slide slide = incline(eng, kBlock, 30, 0.3);
  r.expect_near("3d/incline/block-slides", eng, slide.acceleration, a_slide, 0.01 * a_slide,
                "5 x 5 x 1 cm box, 30 deg, mu = 0.3: g (sin - mu cos) within 1 %");
  const Slide stick = incline(eng, kBlock, 20, 0.5);
  Check& sticks = r.expect_below("3d/incline/block-sticks", eng, stick.distance, 1e-3,
                                 "20 deg, mu = 0.5 > tan 20: moves less than 1e-3 cm in 0.4 s");
  if (eng == "bullet" && !sticks.passed) {
    // The limitation is measured here, not quoted: creep speed at two steps and with 50 iterations.
    const double coarse = incline(eng, kBlock, 20, 0.5, {"accuracy.dt=1e-4"}).distance;
    const double iterated = incline(eng, kBlock, 20, 0.5, {"accuracy.velocity_iterations=50"}).distance;
    sticks.known_limitation(fmt::format(
        "Bullet's sequential-impulse friction lets a resting box creep downhill: {:.2g} cm/s at dt = 1e-5 s, "
        "{:.2g} at 1e-4 s (ratio {:.1f}), {:.2g} with 50 solver iterations. docs/engines.md",
        stick.distance / 0.4, coarse / 0.4, coarse / stick.distance, iterated / 0.4));
  }
  const double a_roll = kG * std::sin(M_PI / 9) / 1.4;
  const Slide roll = incline(eng, kSphere, 20, 0.5);
  r.expect_near("3d/incline/sphere-rolls", eng, roll.acceleration, a_roll, 0.01 * a_roll,
                "sphere, 20 deg, no slip: g sin / (1 + 2/5) within 1 %");

  std::vector<std::pair<std::string, std::vector<std::string>>> variants = {{eng, {}}};
  if (engine_capabilities(eng).soft_contacts)
    variants.push_back({"native-pc", {"accuracy.integrator=predictor-corrector"}});
  std::string rot_text;
  for (const auto& [label, sets] : variants) {
    for (int axis = 0; axis < 3; ++axis) {
      const Rotation rot = torque_free(eng, axis, sets);
      const char* name = axis == 0 ? "largest" : axis == 1 ? "intermediate" : "smallest";
      Check& energy =
          r.expect_below(fmt::format("3d/torque-free/{}-axis/energy", name), label, rot.energy_drift, 1e-3,
                         "1 x 2 x 3 cm box, 10 s at dt = 1e-4 s: relative energy drift below 1e-3");
      if (eng == "ode" && !energy.passed) {
        // Measured here: the drift at half the step shows the order of ODE's gyroscopic update.
        std::vector<std::string> finer = sets;
        finer.push_back("accuracy.dt=5e-5");
        const double half = torque_free(eng, axis, finer).energy_drift;
        energy.known_limitation(
            fmt::format("ODE's gyroscopic update drifts in energy: {:.2g} at dt = 1e-4 s, {:.2g} at 5e-5 s "
                        "(ratio {:.2f}, "
                        "order {:.2f} in dt). docs/engines.md",
                        rot.energy_drift, half, rot.energy_drift / half, std::log2(rot.energy_drift / half)));
      }
      r.expect_below(fmt::format("3d/torque-free/{}-axis/momentum", name), label, rot.momentum_drift, 1e-3,
                     "relative change of the angular momentum vector below 1e-3");
      if (axis == 1)
        r.expect_below(
            "3d/torque-free/intermediate-axis/flips", label, rot.min_ratio, -0.5,
            "spin about the intermediate axis is unstable: its body component reverses (ratio < -0.5)");
      else
        r.expect_near(fmt::format("3d/torque-free/{}-axis/stable", name), label, rot.min_ratio, 1.0, 0.01,
                      "spin about this axis is stable: its body component stays within 1 %");
      rot_text += fmt::format("{} {}: dE {:.1e}, dL {:.1e}, min ratio {:.3f}; ", label, name,
                              rot.energy_drift, rot.momentum_drift, rot.min_ratio);
    }
  }

  std::vector<double> heights;
  for (int k = 0; k < 6; ++k) {
    Vec3 down = Vec3::Zero();
    down[k % 3] = k < 3 ? 1.0 : -1.0;
    heights.push_back(cube_rest_height(eng, down));
    const double expected = 1.0 - down.dot(Vec3(0.2, 0.2, 0.2));
    r.expect_near(fmt::format("3d/loaded-cube/rest-height/face{}", k), eng, heights.back(), expected,
                  0.01 * expected,
                  "2 cm cube, centre of mass 0.2 (1, 1, 1) off centre: rest height 1 - n.c within 1 % (m g "
                  "times it is the potential energy)");
  }
  md += fmt::format(
      "| {} | {:.4f} | {:.2f} (analytic {:.2f}) | {:.2e} | {:.2f} (analytic {:.2f}) | {} | {} |\n", eng, e1,
      slide.acceleration, a_slide, stick.distance, roll.acceleration, a_roll, fmt::join(heights, " / "),
      rot_text);
}

}  // namespace grainlab::validation
