// Bodies held in place (Body3Spec::held), what an impact's active zone is made of: they never move, they
// push back as bodies of their mass, two of them are never computed as a pair, and only the native
// engine takes them.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "engine.hpp"
#include "input_error.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {

constexpr double kR = 0.5, kDensity = 2.65, kKn = 2e5, kG = 981;

// `columns` columns, each of two held spheres overlapping by 0.1 (one on the other) and a free sphere
// dropped onto the upper one from 0.01 above contact; no planes, so only the held spheres can hold it up.
std::string columns_scene(int columns, bool polyhedra) {
  std::string t = R"toml(
[scene]
name = "held columns"
dimension = 3
duration = 1.0
gravity = [0, 0, -981]
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 2e-5
[materials.grain]
k_n = 2e5
restitution = 0.1
k_s = 1.5e5
gamma_s = 20
mu = 0.4
)toml";
  for (int c = 0; c < columns; ++c)
    for (int k = 0; k < 3; ++k) {
      const double z = kR + 2.5 * kR * k;  // (apart: the reader refuses overlaps; held_columns sets them)
      t += fmt::format("[[bodies]]\nshape = \"sphere\"\nradius = {}\ndensity = {}\nposition = [{}, 0, {}]\n",
                       kR, kDensity, 3.0 * c, z);
    }
  if (polyhedra)  // one free cube beside the columns puts the world on the general path
    t += "[[bodies]]\nshape = \"box\"\nsize = [0.5, 0.5, 0.5]\ndensity = 2.65\nposition = [-5, 0, 0]\n";
  return t;
}

Scene held_columns(int columns, bool polyhedra) {
  Scene s = parse_scene(columns_scene(columns, polyhedra), "<held columns>");
  for (Body3Spec& b : s.bodies3d) {
    if (b.shape != Body3Spec::Shape::Sphere) continue;
    const int k = static_cast<int>(std::lround((b.position.z() - kR) / (2.5 * kR)));
    b.position.z() = kR + (k == 0 ? 0 : k == 1 ? 2 * kR - 0.1 : 4 * kR - 0.1 + 0.01);
    b.held = k < 2;
  }
  return s;
}

}  // namespace

// A free sphere on a held one comes to rest where its weight compresses the contact: overlap m g / k_n
// (Hooke's law, analytic), while every held sphere stays where it was to the bit. The held pairs below
// overlap by 0.1 and yet are never a contact. Both the sphere kernel (96 spheres) and the general path
// (a cube among them) do this.
TEST(HeldBodies, StayPutAndHoldUpWhatRestsOnThem) {
  for (const bool general : {false, true}) {
    SCOPED_TRACE(general ? "general path" : "sphere kernel");
    const Scene scene = held_columns(32, general);
    World3d w(scene);
    w.advance_to(0.5);  // restitution 0.1: the dropped spheres settle in a few contact times
    EXPECT_EQ(w.on_sphere_kernel(), !general);
    const double m = kDensity * 4.0 / 3.0 * M_PI * kR * kR * kR;
    const double rest = 4 * kR - 0.1 + kR - m * kG / kKn;  // the free centre's height at rest
    int free = 0;
    for (std::size_t i = 0; i < scene.bodies3d.size(); ++i) {
      const Body3Spec& s = scene.bodies3d[i];
      const Body3& b = w.bodies()[i];
      if (s.shape != Body3Spec::Shape::Sphere) continue;
      if (s.held) {
        EXPECT_EQ(b.x, s.position) << "held sphere " << i << " moved";
        EXPECT_EQ(b.q.coeffs(), s.orientation.coeffs());
        EXPECT_EQ(b.v, Vec3::Zero());
        EXPECT_EQ(b.w, Vec3::Zero());
      } else {
        ++free;
        EXPECT_NEAR(b.x.z(), rest, 1e-3 * m * kG / kKn) << "free sphere " << i;
        EXPECT_NEAR(b.v.norm(), 0, 1e-6);
      }
    }
    EXPECT_EQ(free, 32);
    // One contact per column (free on held); the held pairs' overlaps are not contacts. (The cube falls
    // freely: no planes.)
    EXPECT_EQ(w.count_contacts(), 32u);
  }
}

// Only the native engine holds bodies in place; the others say so instead of letting them fall.
TEST(HeldBodies, OtherEnginesRefuseThem) {
  const Scene scene = held_columns(2, false);
  for (const char* engine : {"ode", "bullet"}) {
    SCOPED_TRACE(engine);
    try {
      make_engine(engine, scene);
      ADD_FAILURE() << engine << " took a held body";
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("hold a body in place"), std::string::npos) << e.message();
    }
  }
  EXPECT_NO_THROW(make_engine("native", scene));
}

}  // namespace grainlab::dem
