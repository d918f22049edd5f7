// Generated assemblies: a lattice bed, and a bed of discs poured into the scene's walls and left to
// settle under the scene's own contact law. Radii and positions come from the scene's seed.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "assembly_common.hpp"
#include "world.hpp"

namespace grainlab::dem {

namespace {

BodySpec disc(const AssemblySpec& a, std::int64_t id, Vec2 pos, double r) {
  BodySpec b;
  b.id = id;
  b.shape = BodySpec::Shape::Disc;
  b.radius = r;
  b.mass = a.spheres ? a.density * 4.0 / 3.0 * M_PI * r * r * r : a.density * M_PI * r * r;
  b.inertia = (a.spheres ? 0.4 : 0.5) * b.mass * r * r;
  b.position = pos;
  b.velocity = a.velocity;
  b.material = a.material;
  b.where = a.where;
  return b;
}

// Drops `a.count` discs from a loose grid above the box and lets them settle with the scene's walls
// and materials (gravity and normal contact always on, the scene's friction and rotation as given).
std::vector<BodySpec> pour(const Scene& scene, const AssemblySpec& a, std::int64_t first_id, Rng& rng) {
  const double rmax = largest_radius(a.radius), pitch = 2.2 * rmax;
  const int cols = std::max(1, static_cast<int>(std::floor(a.width / pitch)));
  Scene settle = settling_scene(scene);
  double mmin = 1e300;
  for (int k = 0; k < a.count; ++k) {
    const double r = draw_radius(a.radius, rng);
    const Vec2 pos{a.origin.x + pitch * (0.5 + k % cols) + rng.uniform(-0.05, 0.05) * rmax,
                   a.origin.y + rmax + pitch * (k / cols)};
    settle.bodies.push_back(disc(a, first_id + k, pos, r));
    settle.bodies.back().velocity = {};
    mmin = std::min(mmin, settle.bodies.back().mass);
  }
  settle.accuracy.dt = settling_dt(scene, mmin);
  World w(settle);
  w.advance_to(a.settle_time);
  std::vector<BodySpec> out = settle.bodies;
  const Particles& p = w.particles();
  for (BodySpec& b : out) {
    const long i = w.index_of(b.id);
    b.position = {p.x[i], p.y[i]};
    b.angle = p.th[i];
    b.velocity = a.velocity;
  }
  return out;
}

}  // namespace

std::vector<BodySpec> expanded_bodies(const Scene& scene) {
  if (scene.assemblies.empty()) return scene.bodies;
  const World w(scene);
  const Particles& p = w.particles();
  std::vector<BodySpec> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    BodySpec b;
    b.id = p.id[i];
    b.shape = p.shape[i] < 0 ? BodySpec::Shape::Disc : BodySpec::Shape::Polygon;
    if (p.shape[i] >= 0) b.vertices = w.polygon_shapes()[p.shape[i]];
    b.radius = p.r[i];
    b.mass = p.m[i];
    b.inertia = p.inertia[i];
    b.position = {p.x[i], p.y[i]};
    b.velocity = {p.vx[i], p.vy[i]};
    b.angle = p.th[i];
    b.spin = p.w[i];
    b.material = p.mat[i];
    out.push_back(b);
  }
  std::sort(out.begin(), out.end(), [](const BodySpec& a, const BodySpec& b) { return a.id < b.id; });
  return out;
}

void World::expand_assemblies() {
  std::int64_t next_id = 0;
  for (std::int64_t id : p_.id) next_id = std::max(next_id, id + 1);
  for (std::size_t k = 0; k < scene_.assemblies.size(); ++k) {
    const AssemblySpec& a = scene_.assemblies[k];
    Rng rng = assembly_rng(scene_, k);
    if (a.kind == AssemblySpec::Kind::Lattice) {
      for (int row = 0; row < a.ny; ++row)
        for (int col = 0; col < a.nx; ++col)
          add_particle(disc(a, next_id++, a.origin + Vec2{col * a.spacing, row * a.spacing},
                            draw_radius(a.radius, rng)));
    } else {
      for (const BodySpec& b : pour(scene_, a, next_id, rng)) add_particle(b);
      next_id += a.count;
    }
  }
}

}  // namespace grainlab::dem
