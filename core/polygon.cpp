#include "polygon.hpp"

#include <algorithm>
#include <cmath>

namespace grainlab {

PolygonMass polygon_mass(const std::vector<Vec2>& v) {
  // Sum over triangles (origin, v_i, v_i+1); exact for any simple polygon.
  double a2 = 0, cx = 0, cy = 0, j = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2 p = v[i], q = v[(i + 1) % v.size()];
    const double c = cross(p, q);
    a2 += c;
    cx += (p.x + q.x) * c;
    cy += (p.y + q.y) * c;
    j += c * (dot(p, p) + dot(p, q) + dot(q, q));
  }
  PolygonMass m;
  m.area = a2 / 2;
  if (m.area == 0) return m;
  m.centroid = {cx / (3 * a2), cy / (3 * a2)};
  // j/12 is the polar moment about the origin; shift to the centroid (parallel axis).
  m.polar_moment_per_density = j / 12 - m.area * dot(m.centroid, m.centroid);
  return m;
}

bool is_convex_ccw(const std::vector<Vec2>& v) {
  if (v.size() < 3) return false;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i], b = v[(i + 1) % v.size()], c = v[(i + 2) % v.size()];
    if (cross(b - a, c - b) <= 0) return false;
  }
  return true;
}

double bounding_radius(const std::vector<Vec2>& v) {
  double r = 0;
  for (Vec2 p : v) r = std::max(r, norm(p));
  return r;
}

std::vector<OverlapVertex> convex_overlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  std::vector<OverlapVertex> out, in;
  out.reserve(a.size() + b.size());
  for (Vec2 p : a) out.push_back({p, false});
  for (size_t e = 0; e < b.size() && !out.empty(); ++e) {
    const Vec2 e0 = b[e], e1 = b[(e + 1) % b.size()];
    const Vec2 d = e1 - e0;
    in.swap(out);
    out.clear();
    for (size_t i = 0; i < in.size(); ++i) {
      const OverlapVertex& cur = in[i];
      const OverlapVertex& nxt = in[(i + 1) % in.size()];
      const double sc = cross(d, cur.p - e0), sn = cross(d, nxt.p - e0);  // > 0: inside (left of edge)
      if (sc >= 0) out.push_back(cur);
      if ((sc >= 0) != (sn >= 0)) {
        const double t = sc / (sc - sn);
        out.push_back({cur.p + (nxt.p - cur.p) * t, true});
      }
    }
  }
  return out;
}

std::vector<Vec2> circle_polygon_crossings(Vec2 c, double r, const std::vector<Vec2>& poly) {
  std::vector<Vec2> pts;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 p = poly[i], d = poly[(i + 1) % poly.size()] - p;
    const Vec2 f = p - c;
    const double A = dot(d, d), B = 2 * dot(f, d), C = dot(f, f) - r * r;
    const double disc = B * B - 4 * A * C;
    if (disc < 0 || A == 0) continue;
    const double s = std::sqrt(disc);
    for (double t : {(-B - s) / (2 * A), (-B + s) / (2 * A)})
      if (t >= 0 && t < 1) pts.push_back(p + d * t);
  }
  return pts;
}

bool point_in_convex(Vec2 p, const std::vector<Vec2>& poly) {
  for (size_t i = 0; i < poly.size(); ++i)
    if (cross(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]) < 0) return false;
  return true;
}

}  // namespace grainlab
