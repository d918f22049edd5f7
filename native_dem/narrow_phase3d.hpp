#pragma once
// Contact geometry between 3-D bodies: spheres, convex polyhedra and planes. Each contact point carries
// the normal pointing from body B into body A (the force on A is along +normal), the overlap depth and
// a feature number that stays the same while the same vertex, edge pair or clipped point is touching,
// so the tangential spring can be kept from step to step.
#include <cstdint>
#include <vector>

#include "polyhedron.hpp"

namespace grainlab::dem {

struct ContactPoint3 {
  Vec3 point, normal;
  double depth = 0;
  int feature = 0;
};

// A body placed in the world. For a polyhedron `world_vertices`, `world_normals` and what the
// separating-axis test needs of them are filled once per force evaluation (place()).
struct Placed3 {
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  double radius = 0;                 // sphere radius, or the polyhedron's bounding radius
  const Polyhedron* hull = nullptr;  // nullptr: a sphere
  std::vector<Vec3> world_vertices, world_normals;
  std::vector<double> world_offsets;
  // Points or directions as separate arrays (x of all, then y, then z), so the separating-axis test can
  // take two at a time.
  struct Coordinates {
    std::vector<double> x, y, z;
    void assign(const std::vector<Vec3>& points);
    Vec3 operator[](std::size_t i) const { return {x[i], y[i], z[i]}; }
  } vertex_coordinates, normal_coordinates;
  // Per edge (when the hull knows its edges' faces), the normal of the plane of the edge's arc on the
  // Gauss map, n(f2) x n(f1): placed once here rather than for every pair the body is in.
  Coordinates arcs;
  // The polyhedron's own extent along each of its face normals (what the separating-axis test would
  // otherwise project again for every pair).
  std::vector<double> face_lo, face_hi;
  // The radius of the largest ball about x inside the hull (its nearest face's distance). The
  // separating-axis test bounds an axis's overlap from below with it and skips the axes that cannot win
  // (hull_hull). Set it below minus the hulls' widths (tests use -1e300) and nothing is skipped.
  double inradius = 0;
  void place();
};

struct Plane3 {
  Vec3 point, normal;
};

// Appends the contacts of A with B (or with a plane) to `out`; returns how many were added.
int sphere_sphere(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out);
int body_plane(const Placed3& a, const Plane3& p, std::vector<ContactPoint3>& out);
int sphere_hull(const Placed3& sphere, const Placed3& hull, bool sphere_is_a,
                std::vector<ContactPoint3>& out);
// A pair's separating axis remembered from one call to the next (kNoHint: none yet). In a resting
// bed the axis that separated two grains last step almost always separates them again, and it is tried
// first: one projection instead of a search. Any axis that separates the hulls proves them apart, so a
// hint only makes the answer sooner, never another: the contacts are the same to the bit with or without.
using SeparatingHint = std::int32_t;
constexpr SeparatingHint kNoHint = -1;
// A touching pair's least axis, kept with the crossings it was found among, while no other axis can have
// come down to it. Each other axis's overlap when the axis was found bounds it from below; a relative
// shift of B by dp (in A's frame) and a relative turn by theta can lower it by at most |dp| + lever * s,
// s = 2 sin(theta / 2), the lever being how far the turn can carry the points that set it (on an edge
// pair's axis, also how fast the axis itself turns). While every bound stays above the least axis's
// overlap now, the full search would find that same axis, so hull_hull projects it alone, and the
// contacts are the same to the bit.
struct LeastAxis {
  SeparatingHint axis = kNoHint;  // kNoHint: none kept
  Vec3 at = Vec3::Zero();         // B's centre in A's frame when found
  Quat turn = Quat(0, 0, 0, 0);   // conj(qA) qB when found
  // Every other face axis overlaps by at least faces - |dp| - face_lever s.
  double faces = 0, face_lever = 0;
  // The edge pairs of the crossings, weighed by 1.05: at least edges - 1.05 |dp| at s = 0 and
  // edges_at_span - 1.05 |dp| at s = span, and the line between them in between (each pair's bound is
  // a line in s); span bounds s while the crossings hold.
  double edges = 0, edges_at_span = 0, span = 0;
};
// A pair's Gauss-map crossings (for each edge of A, the edges of B it forms a face of the Minkowski
// difference with), found from the signs of A's face normals against B's arcs and B's against A's. The
// signs depend only on how B is turned relative to A, so in a resting bed they stay the same from step
// to step: kept here, they are used again while the relative turn since they were found is smaller than
// the least angle by which any of those signs stands from flipping (with an allowance for rounding), so
// the crossings, and the contacts, are the same to the bit as when found afresh.
// A pair that turns past its margin before the crossings serve even once is searched afresh (and
// lazily) for a few calls before they are kept again: finding all of them costs more than one search.
struct GaussCrossings {
  Quat turn = Quat(0, 0, 0, 0);  // conj(qA) qB when found
  double margin = -1;            // 2 sin(half the relative turn since) must stay below it; < 0: none kept
  std::vector<std::uint64_t> partners;
  bool used = false;  // served a search since found
  int rest = 0;       // calls left before keeping them again
  LeastAxis least;    // found among these crossings
};
int hull_hull(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out,
              SeparatingHint* hint = nullptr, GaussCrossings* crossings = nullptr);
int body_body(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out,
              SeparatingHint* hint = nullptr, GaussCrossings* crossings = nullptr);

}  // namespace grainlab::dem
