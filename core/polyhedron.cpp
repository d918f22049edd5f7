#include "polyhedron.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace grainlab {

bool Polyhedron::contains(const Vec3& p) const {
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (plane_distance(static_cast<int>(f), p) > 0) return false;
  return true;
}

int Polyhedron::support(const Vec3& d) const {
  int best = 0;
  double best_h = -1e300;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const double h = d.dot(vertices[i]);
    if (h > best_h) best_h = h, best = static_cast<int>(i);
  }
  return best;
}

double Polyhedron::bounding_radius() const {
  double r = 0;
  for (const Vec3& v : vertices) r = std::max(r, v.norm());
  return r;
}

double Polyhedron::inradius() const {
  double r = 1e300;
  for (const double d : offsets) r = std::min(r, d);
  return std::max(r, 0.0);
}

void Polyhedron::translate(const Vec3& shift) {
  for (Vec3& v : vertices) v += shift;
  for (std::size_t f = 0; f < faces.size(); ++f) offsets[f] += normals[f].dot(shift);
  derive_extents();
}

void Polyhedron::derive_extents() {
  const std::size_t nf = normals.size();
  face_lo.assign(nf, 1e300), face_hi.assign(nf, -1e300);
  for (std::size_t f = 0; f < nf; ++f)
    for (const Vec3& v : vertices) {
      const double s = normals[f].dot(v);
      face_lo[f] = std::min(face_lo[f], s), face_hi[f] = std::max(face_hi[f], s);
    }
  edge_lengths.resize(edges.size());
  for (std::size_t j = 0; j < edges.size(); ++j)
    edge_lengths[j] = (vertices[static_cast<std::size_t>(edges[j].second)] -
                       vertices[static_cast<std::size_t>(edges[j].first)])
                          .norm();
  first_edges.assign(nf, 0), second_edges.assign(nf, 0);
  if (edges.size() > 64 || edge_faces.size() != edges.size()) return;
  for (std::size_t j = 0; j < edges.size(); ++j) {
    first_edges[static_cast<std::size_t>(edge_faces[j].first)] |= std::uint64_t{1} << j;
    second_edges[static_cast<std::size_t>(edge_faces[j].second)] |= std::uint64_t{1} << j;
  }
}

std::string make_polyhedron(std::vector<Vec3> vertices, std::vector<std::vector<int>> faces,
                            Polyhedron& out) {
  const int nv = static_cast<int>(vertices.size());
  if (nv < 4) return "a polyhedron needs at least 4 vertices";
  if (faces.size() < 4) return "a polyhedron needs at least 4 faces";
  Vec3 mean = Vec3::Zero();
  for (const Vec3& v : vertices) mean += v;
  mean /= nv;
  double size = 0;
  for (const Vec3& v : vertices) size = std::max(size, (v - mean).norm());
  Polyhedron p;
  p.vertices = vertices;
  // Each directed edge must appear once and its reverse once: the surface is closed and consistently
  // oriented.
  std::map<std::pair<int, int>, int> directed, face_of;
  std::vector<int> used(static_cast<std::size_t>(nv), 0);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    if (face.size() < 3) return fmt::format("face {} has fewer than 3 vertices", f);
    for (int i : face)
      if (i < 0 || i >= nv) return fmt::format("face {} refers to vertex {}, which does not exist", f, i);
    Vec3 n = Vec3::Zero();  // Newell's normal: robust for any planar polygon
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Vec3 &a = vertices[face[k]], &b = vertices[face[(k + 1) % face.size()]];
      n += (a - mean).cross(b - mean);
      ++directed[{face[k], face[(k + 1) % face.size()]}];
      face_of[{face[k], face[(k + 1) % face.size()]}] = static_cast<int>(f);
      ++used[face[k]];
    }
    if (n.norm() < 1e-12 * size * size) return fmt::format("face {} has no area", f);
    n.normalize();
    const double d = n.dot(vertices[face[0]]);
    for (int i : face)
      if (std::abs(n.dot(vertices[i]) - d) > 1e-9 * size)
        return fmt::format("face {} is not planar (vertex {} is off its plane)", f, i);
    p.normals.push_back(n);
    p.offsets.push_back(d);
  }
  for (const auto& [e, count] : directed) {
    if (count != 1) return fmt::format("edge {}-{} is used twice in the same direction", e.first, e.second);
    if (!directed.count({e.second, e.first}))
      return fmt::format("edge {}-{} belongs to one face only: the faces do not close the solid", e.first,
                         e.second);
    if (e.first < e.second) {
      p.edges.push_back(e);
      p.edge_faces.emplace_back(face_of.at(e), face_of.at({e.second, e.first}));
    }
  }
  for (int i = 0; i < nv; ++i)
    if (!used[i]) return fmt::format("vertex {} belongs to no face", i);
  p.faces = std::move(faces);
  for (std::size_t f = 0; f < p.faces.size(); ++f) {
    if (p.plane_distance(static_cast<int>(f), mean) >= 0)
      return fmt::format("face {} faces inwards (list its vertices counter-clockwise seen from outside)", f);
    for (int i = 0; i < nv; ++i)
      if (p.plane_distance(static_cast<int>(f), vertices[i]) > 1e-9 * size)
        return fmt::format("not convex: vertex {} lies outside the plane of face {}", i, f);
  }
  p.derive_extents();
  out = std::move(p);
  return {};
}

std::vector<Vec3> icosahedron_vertices() {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> ico;
  for (const double s : {-1.0, 1.0})
    for (const double t : {-1.0, 1.0})
      ico.push_back(Vec3(0, s, t * phi).normalized()), ico.push_back(Vec3(s, t * phi, 0).normalized()),
          ico.push_back(Vec3(t * phi, 0, s).normalized());
  return ico;
}

Polyhedron make_box(const Vec3& h) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k)
    v.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(), (k & 4) ? h.z() : -h.z());
  const std::vector<std::vector<int>> faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                               {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  Polyhedron p;
  const std::string err = make_polyhedron(v, faces, p);
  if (!err.empty()) throw std::logic_error("make_box: " + err);
  return p;
}

// Each face is fanned into triangles; each triangle with the reference point r makes a tetrahedron
// whose volume, first and second moments are exact (second moment of a tetrahedron with one vertex at
// the origin: V/20 (sum v v^T + (sum v)(sum v)^T)).
SolidMass polyhedron_mass(const Polyhedron& p) {
  Vec3 r = Vec3::Zero();
  for (const Vec3& v : p.vertices) r += v;
  r /= static_cast<double>(p.vertices.size());
  double volume = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const auto& face : p.faces)
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      const Vec3 a = p.vertices[face[0]] - r, b = p.vertices[face[k]] - r, c = p.vertices[face[k + 1]] - r;
      const double vol = a.dot(b.cross(c)) / 6;
      const Vec3 s = a + b + c;
      volume += vol;
      first += vol * s / 4;
      second += vol / 20 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
  SolidMass m;
  m.volume = volume;
  const Vec3 c = first / volume;
  m.centroid = c + r;
  const Mat3 central = second - volume * c * c.transpose();
  m.inertia_per_density = central.trace() * Mat3::Identity() - central;
  return m;
}

Quat quat_from_rotation_vector(const Vec3& r) {
  const double angle = r.norm();
  if (angle < 1e-300) return Quat::Identity();
  return Quat(Eigen::AngleAxisd(angle, r / angle));
}

}  // namespace grainlab
