// Generated 3-D beds: a simple-cubic lattice of spheres, and spheres poured into the scene's planes and
// left to settle under the scene's own contact law (on this engine's sphere kernel). Radii, jitter and
// so the settled bed come from the scene's seed, one stream per assembly.
#include <algorithm>
#include <cmath>

#include "assembly_common.hpp"
#include "world3d.hpp"

namespace grainlab::dem {

namespace {

Body3Spec sphere(const AssemblySpec& a, std::int64_t id, const Vec3& position, double r) {
  Body3Spec b;
  b.id = id;
  b.shape = Body3Spec::Shape::Sphere;
  b.radius = r;
  b.mass = a.density * 4.0 / 3.0 * M_PI * r * r * r;
  b.inertia = Mat3::Identity() * (0.4 * b.mass * r * r);
  b.position = position;
  b.velocity = a.velocity3;
  b.material = a.material;
  b.where = a.where;
  return b;
}

std::vector<Body3Spec> lattice(const AssemblySpec& a, std::int64_t first_id, Rng& rng) {
  std::vector<Body3Spec> out;
  out.reserve(static_cast<std::size_t>(a.nx) * a.ny * a.nz);
  for (int z = 0; z < a.nz; ++z)
    for (int y = 0; y < a.ny; ++y)
      for (int x = 0; x < a.nx; ++x)
        out.push_back(sphere(a, first_id + static_cast<std::int64_t>(out.size()),
                             a.origin3 + a.spacing * Vec3(x, y, z), draw_radius(a.radius, rng)));
  return out;
}

// Drops `a.count` spheres at rest from a loose grid (pitch 1.1 largest diameters, centred in the box,
// jittered by 5 % of a radius across) above the box width x depth, and lets them settle for settle_time with
// the scene's planes, periodic sides and materials (gravity and normal contact always on; friction and
// rotation as the scene gives them), by velocity Verlet at 1/30 of the stiffest, lightest contact's period.
std::vector<Body3Spec> pour(const Scene& scene, const AssemblySpec& a, std::int64_t first_id, Rng& rng) {
  const double rmax = largest_radius(a.radius), pitch = 2.2 * rmax;
  const int cols = std::max(1, static_cast<int>(std::floor(a.width / pitch)));
  const int rows = std::max(1, static_cast<int>(std::floor(a.depth / pitch)));
  // The grid centred in the box: dropped off-centre, the bed comes to rest tilted across it (a 20 cm
  // deep box holds 9 rows of 2.2 cm with 1.3 cm to spare, and rebounds were deflected sideways).
  const double margin_x = 0.5 * std::max(0.0, a.width - cols * pitch);
  const double margin_y = 0.5 * std::max(0.0, a.depth - rows * pitch);
  Scene settle = settling_scene(scene);
  double mmin = 1e300;
  for (int k = 0; k < a.count; ++k) {
    const double r = draw_radius(a.radius, rng);
    const int col = k % cols, row = (k / cols) % rows, layer = k / (cols * rows);
    // (Drawn one statement each: the order of evaluation of function arguments is unspecified.)
    const double jitter_x = rng.uniform(-0.05, 0.05) * rmax;
    const double jitter_y = rng.uniform(-0.05, 0.05) * rmax;
    const Vec3 at = a.origin3 + Vec3(margin_x + pitch * (0.5 + col) + jitter_x,
                                     margin_y + pitch * (0.5 + row) + jitter_y, rmax + pitch * layer);
    settle.bodies3d.push_back(sphere(a, first_id + k, at, r));
    settle.bodies3d.back().velocity = Vec3::Zero();
    mmin = std::min(mmin, settle.bodies3d.back().mass);
  }
  settle.accuracy.dt = settling_dt(scene, mmin);
  World3d w(settle);
  w.advance_to(a.settle_time);
  std::vector<Body3Spec> out = settle.bodies3d;
  for (std::size_t i = 0; i < out.size(); ++i) {  // the world keeps the scene's order
    const Body3& b = w.bodies()[i];
    out[i].position = b.x;
    out[i].orientation = b.q;
    out[i].velocity = a.velocity3;
  }
  return out;
}

}  // namespace

std::vector<Body3Spec> expanded_bodies3d(const Scene& scene) {
  std::vector<Body3Spec> out = scene.bodies3d;
  std::int64_t next_id = 0;
  for (const Body3Spec& b : out) next_id = std::max(next_id, b.id + 1);
  for (std::size_t k = 0; k < scene.assemblies.size(); ++k) {
    const AssemblySpec& a = scene.assemblies[k];
    Rng rng = assembly_rng(scene, k);
    std::vector<Body3Spec> made =
        a.kind == AssemblySpec::Kind::Lattice ? lattice(a, next_id, rng) : pour(scene, a, next_id, rng);
    next_id += static_cast<std::int64_t>(made.size());
    out.insert(out.end(), std::make_move_iterator(made.begin()), std::make_move_iterator(made.end()));
  }
  return out;
}

}  // namespace grainlab::dem
