#pragma once
// What the generated beds of both dimensions share: radii drawn from the scene's size distribution, one
// random stream per assembly, and the scene a pour settles in.
#include <algorithm>
#include <cmath>

#include "rng.hpp"
#include "scene.hpp"

namespace grainlab::dem {

inline double draw_radius(const SizeDistribution& d, Rng& rng) {
  switch (d.kind) {
    case SizeDistribution::Kind::Fixed:
      return d.a;
    case SizeDistribution::Kind::Uniform:
      return rng.uniform(d.a, d.b);
    case SizeDistribution::Kind::Normal: {
      double z;
      do z = rng.normal();
      while (std::abs(z) > 3);
      return d.a + d.b * z;
    }
  }
  return d.a;
}

inline double largest_radius(const SizeDistribution& d) {
  return d.kind == SizeDistribution::Kind::Fixed     ? d.a
         : d.kind == SizeDistribution::Kind::Uniform ? d.b
                                                     : d.a + 3 * d.b;
}

// The assembly's own random stream: one per assembly, independent of the body count.
inline Rng assembly_rng(const Scene& scene, std::size_t k) {
  return Rng(scene.seed, 1000003 * (k + 1));
}

// The scene a pour settles in: the scene's walls, planes, periodic sides and materials, without its
// bodies and beds, gravity and normal contact on (friction and rotation as the scene gives them), under
// velocity Verlet.
inline Scene settling_scene(const Scene& scene) {
  Scene settle = scene;
  settle.bodies.clear();
  settle.bodies3d.clear();
  settle.assemblies.clear();
  settle.effects.set(Effect::gravity);
  settle.effects.set(Effect::normal_contact);
  settle.accuracy.integrator = Integrator::VelocityVerlet;
  // A 3-D bed settles into the box as the scene starts: a moving plane held where it is at t = 0 (a pour
  // onto a vibrating floor would never settle).
  for (PlaneSpec& p : settle.planes)
    if (p.motion.active()) p.point += p.motion.shift(0), p.motion = Motion3{};
  return settle;
}

// A step of 1/30 of the stiffest contact's period on the lightest grain: stable for the linear law.
inline double settling_dt(const Scene& scene, double lightest_mass) {
  double kmax = 0;
  for (const Material& m : scene.materials) kmax = std::max(kmax, m.k_n);
  return M_PI * std::sqrt(0.5 * lightest_mass / kmax) / 30;
}

}  // namespace grainlab::dem
