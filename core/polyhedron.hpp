#pragma once
// Convex polyhedra for 3-D bodies: checked construction from vertices and faces, mass properties
// (volume, centroid, inertia tensor) and the queries the narrow phase needs.
#include <Eigen/Dense>
#include <cstdint>
#include <string>
#include <vector>

namespace grainlab {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

struct Polyhedron {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;     // vertex indices, counter-clockwise seen from outside
  std::vector<Vec3> normals;               // outward unit normal per face
  std::vector<double> offsets;             // plane of face f: normals[f] . x = offsets[f]
  std::vector<std::pair<int, int>> edges;  // each edge once, a < b
  // Per edge, the two faces that meet there: the one that runs a -> b, then the one that runs b -> a.
  std::vector<std::pair<int, int>> edge_faces;
  // Kept by make_polyhedron and translate for the narrow phase, which would otherwise find them for every
  // placed grain at every step or for every pair: each face's extent along its own normal, [face_lo,
  // face_hi] (a turn and a shift of the body add only n . x); and per face, the edges whose first (second)
  // face it is (bit j for edge j, hulls of up to 64 edges), where the Gauss-map search starts.
  std::vector<double> face_lo, face_hi;
  std::vector<std::uint64_t> first_edges, second_edges;
  std::vector<double> edge_lengths;  // per edge (how fast its pairs' axes can turn: narrow_phase3d)

  // Signed distance of p from the plane of face f (positive outside).
  double plane_distance(int f, const Vec3& p) const { return normals[f].dot(p) - offsets[f]; }
  bool contains(const Vec3& p) const;
  // The vertex furthest along direction d.
  int support(const Vec3& d) const;
  double bounding_radius() const;  // about the frame origin
  // The radius of the largest ball about the frame origin inside the hull (its nearest face's distance;
  // 0 when the origin is outside).
  double inradius() const;
  void translate(const Vec3& shift);
  void derive_extents();  // face_lo, face_hi, first_edges, second_edges and edge_lengths from the rest
};

// Builds and checks a polyhedron. Returns an empty string on success, else what is wrong (faces not
// closed, not convex, wrongly oriented, degenerate).
std::string make_polyhedron(std::vector<Vec3> vertices, std::vector<std::vector<int>> faces, Polyhedron& out);
// An axis-aligned box centred on the origin.
Polyhedron make_box(const Vec3& half_extents);
// The 12 vertices of a regular icosahedron of circumradius 1 centred on the origin (the seed of the
// irregular grains).
std::vector<Vec3> icosahedron_vertices();

struct SolidMass {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  Mat3 inertia_per_density = Mat3::Zero();  // about the centroid
};
SolidMass polyhedron_mass(const Polyhedron& p);

// Rotation vector (axis times angle) as a unit quaternion.
Quat quat_from_rotation_vector(const Vec3& r);

}  // namespace grainlab
