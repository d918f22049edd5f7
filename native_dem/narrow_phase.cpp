#include "narrow_phase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainlab::dem {

namespace {

void world_outline(const BodyPose& b, std::vector<Vec2>& out) {
  out.clear();
  const double c = std::cos(b.angle), s = std::sin(b.angle);
  for (Vec2 v : *b.vertices) out.push_back({b.centre.x + c * v.x - s * v.y, b.centre.y + s * v.x + c * v.y});
}

// The two points of `pts` furthest apart.
bool furthest_pair(const std::vector<Vec2>& pts, Vec2& p, Vec2& q) {
  double best = -1;
  for (std::size_t a = 0; a < pts.size(); ++a)
    for (std::size_t b = a + 1; b < pts.size(); ++b) {
      const Vec2 d = pts[a] - pts[b];
      if (dot(d, d) > best) best = dot(d, d), p = pts[a], q = pts[b];
    }
  return best > 0;
}

// Normal perpendicular to the chord p-q, oriented from b towards a.
Vec2 chord_normal(Vec2 p, Vec2 q, Vec2 a_centre, Vec2 b_centre) {
  const Vec2 d = q - p;
  Vec2 n = Vec2{-d.y, d.x} * (1 / norm(d));
  return dot(n, a_centre - b_centre) < 0 ? -n : n;
}

// Points where two closed outlines cross (edge-edge intersections).
void outline_crossings(const std::vector<Vec2>& a, const std::vector<Vec2>& b, std::vector<Vec2>& out) {
  out.clear();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2 p = a[i], r = a[(i + 1) % a.size()] - p;
    for (std::size_t k = 0; k < b.size(); ++k) {
      const Vec2 q = b[k], s = b[(k + 1) % b.size()] - q;
      const double den = cross(r, s);
      if (den == 0) continue;  // parallel edges: their end points are found by the neighbouring edges
      const double t = cross(q - p, s) / den, u = cross(q - p, r) / den;
      if (t >= 0 && t < 1 && u >= 0 && u < 1) out.push_back(p + r * t);
    }
  }
}

bool polygon_polygon(const BodyPose& a, const BodyPose& b, ContactGeometry& c, std::vector<Vec2>& oa,
                     std::vector<Vec2>& ob) {
  world_outline(a, oa);
  world_outline(b, ob);
  const std::vector<OverlapVertex> ov = convex_overlap(oa, ob);
  if (ov.size() < 3) return false;
  std::vector<Vec2> crossings, all;
  for (const OverlapVertex& v : ov) all.push_back(v.p);
  outline_crossings(oa, ob, crossings);
  Vec2 p, q, point;
  if (crossings.size() >= 2 && furthest_pair(crossings, p, q)) {
    point = (p + q) * 0.5;
    const Vec2 d = q - p;
    c.normal = Vec2{-d.y, d.x} * (1 / norm(d));
    // Orient from b to a: a's vertices inside b lie on the -n side of the contact line, b's inside a
    // on the +n side. (The centre-to-centre direction can flip sign mid-contact; this cannot.)
    double side = 0;
    for (Vec2 v : oa)
      if (point_in_convex(v, ob)) side -= dot(v - point, c.normal);
    for (Vec2 v : ob)
      if (point_in_convex(v, oa)) side += dot(v - point, c.normal);
    if (side < 0 || (side == 0 && dot(c.normal, a.centre - b.centre) < 0)) c.normal = -c.normal;
  } else {  // one outline inside the other: no crossing line, push centre from centre
    const Vec2 d = a.centre - b.centre;
    c.normal = norm(d) > 0 ? d * (1 / norm(d)) : Vec2{0, 1};
    point = polygon_mass(all).centroid;
  }
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (Vec2 v : all) lo = std::min(lo, dot(v, c.normal)), hi = std::max(hi, dot(v, c.normal));
  c.depth = hi - lo;
  if (c.depth <= 0) return false;
  c.arm_i = point - a.centre;
  c.arm_j = point - b.centre;
  return true;
}

// a: the polygon, disc: the disc. Normal returned from the polygon towards the disc.
bool polygon_disc(const BodyPose& poly, const BodyPose& disc, ContactGeometry& c,
                  std::vector<Vec2>& outline) {
  world_outline(poly, outline);
  const std::vector<Vec2> crossings = circle_polygon_crossings(disc.centre, disc.radius, outline);
  Vec2 p, q;
  if (crossings.size() < 2 || !furthest_pair(crossings, p, q))
    return false;  // no crossing: apart or enclosed
  c.normal = chord_normal(p, q, disc.centre, poly.centre);
  // The overlap region spans the chord, the polygon's vertices inside the disc, and the disc's
  // deepest point if it lies inside the polygon.
  double lo = dot(p, c.normal), hi = lo;
  for (Vec2 v : outline)
    if (dot(v - disc.centre, v - disc.centre) < disc.radius * disc.radius)
      lo = std::min(lo, dot(v, c.normal)), hi = std::max(hi, dot(v, c.normal));
  const Vec2 deepest = disc.centre - c.normal * disc.radius;
  if (point_in_convex(deepest, outline))
    lo = std::min(lo, dot(deepest, c.normal)), hi = std::max(hi, dot(deepest, c.normal));
  c.depth = hi - lo;
  if (c.depth <= 0) return false;
  const Vec2 point = (p + q) * 0.5;
  c.arm_i = point - disc.centre;
  c.arm_j = point - poly.centre;
  return true;
}

}  // namespace

bool disc_wall_contact(Vec2 centre, double radius, const Wall& wall, ContactGeometry& c) {
  if (wall.spec.kind == WallSpec::Kind::Line) {
    const double gap = dot(centre - wall.a, wall.normal);
    if (gap >= radius) return false;
    c.normal = wall.normal;
    c.depth = radius - gap;
  } else {
    const Vec2 d = wall.b - wall.a;
    const double t = std::clamp(dot(centre - wall.a, d) / dot(d, d), 0.0, 1.0);
    const Vec2 off = centre - (wall.a + d * t);
    const double dist2 = dot(off, off);
    if (dist2 >= radius * radius || dist2 == 0) return false;
    const double dist = std::sqrt(dist2);
    c.normal = off * (1 / dist);
    c.depth = radius - dist;
  }
  c.arm_i = c.normal * -radius;  // the disc's surface point, as r_i w_i in eq. 2.3
  c.arm_j = {};
  return true;
}

bool vertex_wall_contact(const BodyPose& body, std::size_t v, const Wall& wall, ContactGeometry& c) {
  const Vec2 arm = rotate((*body.vertices)[v], body.angle);
  const Vec2 p = body.centre + arm;
  const double gap = dot(p - wall.a, wall.normal);
  if (gap >= 0 || gap < -2 * body.radius) return false;
  if (wall.spec.kind == WallSpec::Kind::Segment) {
    const Vec2 d = wall.b - wall.a;
    const double t = dot(p - wall.a, d) / dot(d, d);
    if (t < 0 || t > 1) return false;
  }
  c.normal = wall.normal;
  c.depth = -gap;
  c.arm_i = arm;
  c.arm_j = {};
  return true;
}

bool body_body_contact(const BodyPose& a, const BodyPose& b, ContactGeometry& c, std::vector<Vec2>& sa,
                       std::vector<Vec2>& sb) {
  const Vec2 d = a.centre - b.centre;
  if (dot(d, d) >= (a.radius + b.radius) * (a.radius + b.radius)) return false;
  if (a.vertices && b.vertices) return polygon_polygon(a, b, c, sa, sb);
  if (a.vertices) {  // polygon a, disc b: geometry computed with the disc first, then flipped
    if (!polygon_disc(a, b, c, sa)) return false;
    c.normal = -c.normal;
    std::swap(c.arm_i, c.arm_j);
    return true;
  }
  if (b.vertices) return polygon_disc(b, a, c, sb);
  // Two discs (only reached from tests; the engine uses the fast kernel).
  const double dist = norm(d);
  if (dist == 0) return false;
  c.normal = d * (1 / dist);
  c.depth = a.radius + b.radius - dist;
  c.arm_i = c.normal * -a.radius;
  c.arm_j = c.normal * b.radius;
  return true;
}

}  // namespace grainlab::dem
