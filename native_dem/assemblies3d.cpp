// Generated 3-D beds: a simple-cubic lattice of spheres, and spheres or irregular convex grains poured
// into the scene's planes and left to settle under the scene's own contact law (spheres on this engine's
// sphere kernel, polyhedra on its general path). Radii, shapes, jitter and so the settled bed come from
// the scene's seed, one stream per assembly.
#include <algorithm>
#include <cmath>
#include <stdexcept>

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

// The faces of the convex hull of a few points, each counter-clockwise seen from outside, found by
// testing every triple: a face has every other point strictly on its inner side. Empty when four points
// are (nearly) coplanar, which the caller redraws.
std::vector<std::vector<int>> hull_faces(const std::vector<Vec3>& p) {
  std::vector<std::vector<int>> faces;
  const int n = static_cast<int>(p.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const Vec3 nrm = (p[j] - p[i]).cross(p[k] - p[i]).normalized();
        int above = 0, below = 0, flat = 0;
        for (int m = 0; m < n; ++m) {
          if (m == i || m == j || m == k) continue;
          const double d = nrm.dot(p[m] - p[i]);
          (d > 1e-6 ? above : d < -1e-6 ? below : flat)++;
        }
        if (flat > 0 && (above == 0 || below == 0)) return {};  // four points on a face's plane
        if (above == 0) faces.push_back({i, j, k});
        if (below == 0) faces.push_back({i, k, j});
      }
  return faces;
}

// A uniformly random rotation (Shoemake's method).
Quat random_rotation(Rng& rng) {
  const double u1 = rng.uniform(), u2 = 2 * M_PI * rng.uniform(), u3 = 2 * M_PI * rng.uniform();
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Quat(a * std::sin(u2), a * std::cos(u2), b * std::sin(u3), b * std::cos(u3)).normalized();
}

// An irregular convex grain with the volume of the sphere of radius r, in its body frame (origin at the
// centroid): the icosahedron's vertices moved by up to `irregularity` of the radius along and across
// their directions, the whole stretched along three random axes by 1 +- up to `elongation`.
Polyhedron irregular_hull(const AssemblySpec& a, double r, Rng& rng) {
  const std::vector<Vec3> ico = icosahedron_vertices();
  for (;;) {
    const Quat axes = random_rotation(rng);
    Vec3 stretch;
    for (int k = 0; k < 3; ++k) stretch[k] = 1 + a.elongation * rng.uniform(-1, 1);
    const Mat3 shape = axes.toRotationMatrix() * stretch.asDiagonal() * axes.toRotationMatrix().transpose();
    std::vector<Vec3> p;
    for (const Vec3& v : ico) {
      Vec3 wobble;
      for (int k = 0; k < 3; ++k) wobble[k] = a.irregularity * rng.uniform(-1, 1);
      p.push_back(shape * ((v + wobble).normalized() * (1 + a.irregularity * rng.uniform(-1, 1))));
    }
    const std::vector<std::vector<int>> faces = hull_faces(p);
    // Points the others enclose are left out (their indices renumbered).
    std::vector<int> index(p.size(), -1);
    std::vector<Vec3> used;
    for (const auto& f : faces)
      for (int v : f)
        if (index[v] < 0) index[v] = static_cast<int>(used.size()), used.push_back(p[v]);
    std::vector<std::vector<int>> renumbered = faces;
    for (auto& f : renumbered)
      for (int& v : f) v = index[v];
    Polyhedron hull;
    if (faces.empty() || !make_polyhedron(used, renumbered, hull).empty()) continue;
    const SolidMass m = polyhedron_mass(hull);
    const double scale = r * std::cbrt(4 * M_PI / 3 / m.volume);
    for (Vec3& v : used) v = (v - m.centroid) * scale;
    if (!make_polyhedron(used, renumbered, hull).empty()) continue;
    return hull;
  }
}

Body3Spec irregular_grain(const AssemblySpec& a, std::int64_t id, double r, Rng& rng) {
  Body3Spec b;
  b.id = id;
  b.shape = Body3Spec::Shape::Polyhedron;
  b.hull = irregular_hull(a, r, rng);
  const SolidMass m = polyhedron_mass(b.hull);
  b.mass = a.density * m.volume;
  b.inertia = m.inertia_per_density * a.density;
  b.radius = b.hull.bounding_radius();
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

// A pour: `a.count` grains dropped at rest from a loose grid (pitch 1.1 largest diameters, centred in the
// box, jittered by 5 % of a radius across) above the box width x depth, settling for settle_time with the
// scene's planes, periodic sides and materials (gravity and normal contact always on; friction and rotation
// as the scene gives them), by velocity Verlet at 1/30 of the stiffest, lightest contact's period.
// Polyhedra are drawn first (their shapes set the pitch: 1.1 largest bounding diameters). pour_drop is the
// settling scene with the grains at their drop; pour runs it.
Scene pour_drop(const Scene& scene, const AssemblySpec& a, std::int64_t first_id, Rng& rng) {
  std::vector<Body3Spec> grains;
  double rmax = largest_radius(a.radius);
  if (a.polyhedra) {
    for (int k = 0; k < a.count; ++k)
      grains.push_back(irregular_grain(a, first_id + k, draw_radius(a.radius, rng), rng));
    rmax = 0;
    for (const Body3Spec& b : grains) rmax = std::max(rmax, b.radius);
  }
  const double pitch = 2.2 * rmax;
  const int cols = std::max(1, static_cast<int>(std::floor(a.width / pitch)));
  const int rows = std::max(1, static_cast<int>(std::floor(a.depth / pitch)));
  // The grid centred in the box: dropped off-centre, the bed comes to rest tilted across it (a 20 cm
  // deep box holds 9 rows of 2.2 cm with 1.3 cm to spare, and rebounds were deflected sideways).
  const double margin_x = 0.5 * std::max(0.0, a.width - cols * pitch);
  const double margin_y = 0.5 * std::max(0.0, a.depth - rows * pitch);
  Scene settle = settling_scene(scene);
  double mmin = 1e300;
  for (int k = 0; k < a.count; ++k) {
    const double r = a.polyhedra ? 0.0 : draw_radius(a.radius, rng);
    const int col = k % cols, row = (k / cols) % rows, layer = k / (cols * rows);
    // (Drawn one statement each: the order of evaluation of function arguments is unspecified.)
    const double jitter_x = rng.uniform(-0.05, 0.05) * rmax;
    const double jitter_y = rng.uniform(-0.05, 0.05) * rmax;
    const Vec3 at = a.origin3 + Vec3(margin_x + pitch * (0.5 + col) + jitter_x,
                                     margin_y + pitch * (0.5 + row) + jitter_y, rmax + pitch * layer);
    settle.bodies3d.push_back(a.polyhedra ? grains[static_cast<std::size_t>(k)]
                                          : sphere(a, first_id + k, at, r));
    settle.bodies3d.back().position = at;
    settle.bodies3d.back().velocity = Vec3::Zero();
    mmin = std::min(mmin, settle.bodies3d.back().mass);
  }
  settle.accuracy.dt = settling_dt(scene, mmin);
  return settle;
}

std::vector<Body3Spec> pour(const Scene& scene, const AssemblySpec& a, std::int64_t first_id, Rng& rng) {
  const Scene settle = pour_drop(scene, a, first_id, rng);
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

Scene pour_settling_scene(const Scene& scene) {
  if (!scene.bodies3d.empty() || scene.assemblies.size() != 1 ||
      scene.assemblies[0].kind == AssemblySpec::Kind::Lattice)
    throw std::invalid_argument("pour_settling_scene: a scene of one poured assembly and no other bodies");
  Rng rng = assembly_rng(scene, 0);
  return pour_drop(scene, scene.assemblies[0], 0, rng);
}

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
