#include "narrow_phase3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace grainlab::dem {

namespace {

// Two doubles in one SSE2 register. Each lane does the scalar IEEE arithmetic of Eigen's 3-vector dot,
// (a0 b0 + a1 b1) + a2 b2, so two at a time gives the bits of one at a time.
typedef double Two __attribute__((vector_size(16)));
typedef std::int64_t TwoMasks __attribute__((vector_size(16)));
inline Two two(double v) {
  return Two{v, v};
}
inline Two load_two(const double* p) {
  Two t;
  std::memcpy(&t, p, sizeof t);
  return t;
}
// The lanes of a comparison (all ones or zero) as bits 0 and 1.
inline unsigned signs(const TwoMasks& m) {
#ifdef __SSE2__
  return static_cast<unsigned>(_mm_movemask_pd(reinterpret_cast<__m128d>(m)));
#else
  return unsigned(m[0] & 1) | unsigned(m[1] & 1) << 1;
#endif
}
// n . p for points p = (x[i], y[i], z[i]) and (x[i + 1], ...).
inline Two dots(const Two& nx, const Two& ny, const Two& nz, const Placed3::Coordinates& c, std::size_t i) {
  return (nx * load_two(&c.x[i]) + ny * load_two(&c.y[i])) + nz * load_two(&c.z[i]);
}

// Projection interval of a placed hull on axis n.
void project(const Placed3& h, const Vec3& n, double& lo, double& hi) {
  const Placed3::Coordinates& c = h.vertex_coordinates;
  const std::size_t nv = c.x.size();
  const Two nx = two(n.x()), ny = two(n.y()), nz = two(n.z());
  Two lo2 = two(1e300), hi2 = two(-1e300);
  std::size_t i = 0;
  for (; i + 2 <= nv; i += 2) {
    const Two s = dots(nx, ny, nz, c, i);
    lo2 = s < lo2 ? s : lo2;  // std::min and std::max, lane by lane
    hi2 = hi2 < s ? s : hi2;
  }
  lo = std::min(lo2[0], lo2[1]), hi = std::max(hi2[0], hi2[1]);
  for (; i < nv; ++i) {
    const double s = (n.x() * c.x[i] + n.y() * c.y[i]) + n.z() * c.z[i];
    lo = std::min(lo, s), hi = std::max(hi, s);
  }
}

}  // namespace

void Placed3::place() {
  if (!hull) return;
  const Mat3 R = q.toRotationMatrix();
  world_vertices.resize(hull->vertices.size());
  for (std::size_t i = 0; i < hull->vertices.size(); ++i) world_vertices[i] = x + R * hull->vertices[i];
  world_normals.resize(hull->normals.size());
  world_offsets.resize(hull->normals.size());
  for (std::size_t f = 0; f < hull->normals.size(); ++f) {
    world_normals[f] = R * hull->normals[f];
    world_offsets[f] = world_normals[f].dot(world_vertices[hull->faces[f][0]]);
  }
  vertex_coordinates.assign(world_vertices);
  normal_coordinates.assign(world_normals);
  const std::size_t ne = hull->edge_faces.size();
  arcs.x.resize(ne), arcs.y.resize(ne), arcs.z.resize(ne);
  for (std::size_t i = 0; i < ne; ++i) {
    const auto [f1, f2] = hull->edge_faces[i];
    const Vec3 arc = world_normals[f2].cross(world_normals[f1]);
    arcs.x[i] = arc.x(), arcs.y[i] = arc.y(), arcs.z[i] = arc.z();
  }
  face_lo.resize(world_normals.size()), face_hi.resize(world_normals.size());
  for (std::size_t f = 0; f < world_normals.size(); ++f) {  // the hull's own extents, moved by n . x
    const double along = world_normals[f].dot(x);
    face_lo[f] = hull->face_lo[f] + along, face_hi[f] = hull->face_hi[f] + along;
  }
  inradius = hull->inradius();
}

void Placed3::Coordinates::assign(const std::vector<Vec3>& points) {
  x.resize(points.size()), y.resize(points.size()), z.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    x[i] = points[i].x(), y[i] = points[i].y(), z[i] = points[i].z();
}

int sphere_sphere(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out) {
  const Vec3 d = a.x - b.x;
  const double dist = d.norm(), depth = a.radius + b.radius - dist;
  if (depth <= 0 || dist == 0) return 0;
  const Vec3 n = d / dist;
  out.push_back({b.x + n * (b.radius - depth / 2), n, depth, 0});
  return 1;
}

int body_plane(const Placed3& a, const Plane3& p, std::vector<ContactPoint3>& out) {
  if (!a.hull) {
    const double depth = a.radius - p.normal.dot(a.x - p.point);
    if (depth <= 0) return 0;
    out.push_back({a.x - p.normal * (a.radius - depth / 2), p.normal, depth, 0});
    return 1;
  }
  // A polyhedron touches a plane at its vertices, as the thesis's die does.
  if (p.normal.dot(a.x - p.point) > a.radius) return 0;
  int added = 0;
  for (std::size_t i = 0; i < a.world_vertices.size(); ++i) {
    const double depth = -p.normal.dot(a.world_vertices[i] - p.point);
    if (depth > 0) {
      out.push_back({a.world_vertices[i], p.normal, depth, static_cast<int>(i)});
      ++added;
    }
  }
  return added;
}

namespace {

Vec3 closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return a + t * d;
}

// Closest point of face f (placed) to p, assuming p is on the face's outer side.
Vec3 closest_on_face(const Placed3& h, int f, const Vec3& p) {
  const auto& face = h.hull->faces[f];
  const Vec3& n = h.world_normals[f];
  const Vec3 proj = p - n * (n.dot(p) - h.world_offsets[f]);
  bool inside = true;
  for (std::size_t k = 0; k < face.size() && inside; ++k) {
    const Vec3 &a = h.world_vertices[face[k]], &b = h.world_vertices[face[(k + 1) % face.size()]];
    inside = (b - a).cross(proj - a).dot(n) >= 0;
  }
  if (inside) return proj;
  Vec3 best = proj;
  double best_d = 1e300;
  for (std::size_t k = 0; k < face.size(); ++k) {
    const Vec3 c =
        closest_on_segment(p, h.world_vertices[face[k]], h.world_vertices[face[(k + 1) % face.size()]]);
    if ((c - p).squaredNorm() < best_d) best_d = (c - p).squaredNorm(), best = c;
  }
  return best;
}

// Which of the vectors c lie strictly below the plane through 0 with normal `arc` (bit k of `below`) and
// which strictly above (`above`): a hull's face normals against one of the other hull's arcs, or its arcs
// against one of the other's face normals. Up to 64 vectors.
[[gnu::always_inline]] inline void sides_of(const Vec3& arc, const Placed3::Coordinates& c,
                                            std::uint64_t& below, std::uint64_t& above) {
  const std::size_t nf = c.x.size();
  const Two ax = two(arc.x()), ay = two(arc.y()), az = two(arc.z()), zero = two(0);
  below = 0, above = 0;
  std::size_t k = 0;
  for (; k + 2 <= nf; k += 2) {
    const Two side = dots(ax, ay, az, c, k);
    below |= std::uint64_t(signs(side < zero)) << k;
    above |= std::uint64_t(signs(side > zero)) << k;
  }
  for (; k < nf; ++k) {
    const double side = (arc.x() * c.x[k] + arc.y() * c.y[k]) + arc.z() * c.z[k];
    below |= std::uint64_t{side < 0} << k;
    above |= std::uint64_t{side > 0} << k;
  }
}

// Closest points of segments p1-q1 and p2-q2 (clamped), returned as their midpoint.
Vec3 segment_midpoint(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, double& gap) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
  const double den = a * e - b * b;
  double s = den > 1e-14 * a * e ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) t = 0, s = std::clamp(-c / a, 0.0, 1.0);
  if (t > 1) t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
  const Vec3 c1 = p1 + d1 * s, c2 = p2 + d2 * t;
  gap = (c1 - c2).norm();
  return (c1 + c2) / 2;
}

struct Axis {
  double overlap = 1e300;
  Vec3 n;          // from B to A
  int kind = -1;   // 0: face of A, 1: face of B, 2: edge pair
  int index = -1;  // face index, or edge pair ea * 4096 + eb
};

// Overlap of A and B along unit axis n, oriented so that A lies on the positive side. false: separated.
bool overlap_of(double alo, double ahi, double blo, double bhi, Vec3 n, Axis& best, int kind, int index,
                double bias) {
  if (ahi <= blo || bhi <= alo) return false;
  double ov = bhi - alo;  // A on the + side
  if (ahi - blo < ov) ov = ahi - blo, n = -n;
  if (ov * bias < best.overlap) best = {ov * bias, n, kind, index};
  return true;
}
bool overlap_on(const Placed3& a, const Placed3& b, const Vec3& n, Axis& best, int kind, int index,
                double bias) {
  double alo, ahi, blo, bhi;
  project(a, n, alo, ahi);
  project(b, n, blo, bhi);
  return overlap_of(alo, ahi, blo, bhi, n, best, kind, index, bias);
}
// On a face normal of A (kind 0) or of B (kind 1), whose own projection place() has already taken.
bool overlap_on_face(const Placed3& a, const Placed3& b, int kind, std::size_t f, Axis& best) {
  const Placed3& owner = kind == 0 ? a : b;
  const Vec3& n = owner.world_normals[f];
  double lo, hi;
  project(kind == 0 ? b : a, n, lo, hi);
  return kind == 0 ? overlap_of(a.face_lo[f], a.face_hi[f], lo, hi, n, best, 0, static_cast<int>(f), 1.0)
                   : overlap_of(lo, hi, b.face_lo[f], b.face_hi[f], n, best, 1, static_cast<int>(f), 1.0);
}

// Sutherland-Hodgman: the part of polygon `in` on the inner side of plane n.x <= d, into `out`.
void clip(const std::vector<Vec3>& in, const Vec3& n, double d, std::vector<Vec3>& out) {
  out.clear();
  for (std::size_t k = 0; k < in.size(); ++k) {
    const Vec3 &p = in[k], &q = in[(k + 1) % in.size()];
    const double dp = n.dot(p) - d, dq = n.dot(q) - d;
    if (dp <= 0) out.push_back(p);
    if ((dp < 0) != (dq < 0) && dp != dq) out.push_back(p + (q - p) * (dp / (dp - dq)));
  }
}

// Face contact: the incident face of `inc` (most opposed to the reference face of `ref`) is clipped by
// the reference face's side planes; its points below the reference plane are the contacts.
int face_contacts(const Placed3& ref, int rf, const Placed3& inc, bool ref_is_b,
                  std::vector<ContactPoint3>& out) {
  const Vec3 nr = ref.world_normals[rf];
  int inc_face = 0;
  double most = 1e300;
  for (std::size_t f = 0; f < inc.world_normals.size(); ++f)
    if (inc.world_normals[f].dot(nr) < most)
      most = inc.world_normals[f].dot(nr), inc_face = static_cast<int>(f);
  // The polygon and its clipped copy, kept between calls (a bed clips thousands of faces a step).
  static thread_local std::vector<Vec3> poly, clipped;
  poly.clear();
  for (int i : inc.hull->faces[inc_face]) poly.push_back(inc.world_vertices[i]);
  const auto& rface = ref.hull->faces[rf];
  for (std::size_t k = 0; k < rface.size() && !poly.empty(); ++k) {
    const Vec3 &a = ref.world_vertices[rface[k]], &b = ref.world_vertices[rface[(k + 1) % rface.size()]];
    const Vec3 side = (b - a).cross(nr).normalized();  // outward in the reference face's plane
    clip(poly, side, side.dot(a), clipped);
    poly.swap(clipped);
  }
  int added = 0;
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const double depth = ref.world_offsets[rf] - nr.dot(poly[k]);
    if (depth <= 0) continue;
    // The normal points from B into A: the reference normal if the reference body is B.
    const Vec3 n = ref_is_b ? nr : Vec3(-nr);
    out.push_back({poly[k] + nr * (depth / 2), n, depth, 100000 + inc_face * 64 + static_cast<int>(k)});
    ++added;
  }
  return added;
}

// Whether kept crossings are those a fresh search would find at relative turn `turn` (conj(qA) qB).
bool crossings_hold(const GaussCrossings& kept, const Placed3& a, const Quat& turn) {
  return kept.rest == 0 && kept.margin > 0 && kept.partners.size() == a.hull->edges.size() &&
         2 * (kept.turn.conjugate() * turn).vec().norm() < kept.margin;
}

// Only edge pairs that form a face of the Minkowski difference A - B can give the least overlap (or
// separate the two): those whose arcs on the Gauss map cross, the arc of A's edge running between the
// normals of its two faces, the arc of B's between its two negated. The other pairs' axes overlap more
// than some face's, so skipping them changes no result, and it leaves a few dozen of an irregular grain
// pair's 900 edge pairs to project.
//
// The test needs, for each edge, on which side of its arc's plane each face normal of the other body
// lies: for A's edge i, bit k of neg_a (pos_a) is set when B's face normal k is strictly below
// (above) it; for B's edges the same over A's faces, stored the other way round: bit j of neg_b[k]
// (pos_b[k]) when A's face normal k is below (above) B's edge j's arc. With B's edges grouped by their
// faces (bit j of first_b[k] when k is B's edge j's first face, second_b[k] its second), all of B's
// partners of A's edge i come out of a few dozen word operations (partners()), in the order of j, instead
// of a test per pair. Up to 64 faces a body and 64 edges for B; larger bodies, or bodies without their
// edges' faces, have every pair tested.
class MinkowskiEdgePairs {
 public:
  MinkowskiEdgePairs(const Placed3& a, const Placed3& b)
      : a_(a),
        b_(b),
        usable_(a.hull->edge_faces.size() == a.hull->edges.size() &&
                b.hull->edge_faces.size() == b.hull->edges.size() && a.world_normals.size() <= 64 &&
                b.world_normals.size() <= 64 && b.hull->edges.size() <= 64) {
    if (usable_) first_b_ = b.hull->first_edges.data(), second_b_ = b.hull->second_edges.data();
  }
  bool usable() const { return usable_; }
  bool kept() const { return kept_ != nullptr; }  // the crossings are the kept ones: partners() costs a look
  // With `kept` (when usable()): its crossings if they still hold at this relative turn, else all of
  // them found now and kept with their margin.
  void keep_in(GaussCrossings& kept) {
    constexpr int kRest = 8;
    if (kept.rest > 0) {
      --kept.rest;
      return;
    }
    const Quat turn = a_.q.conjugate() * b_.q;
    if (crossings_hold(kept, a_, turn)) {
      kept.used = true;
      kept_ = &kept;
      return;
    }
    kept.least.axis = kNoHint;                   // (found among crossings no longer held)
    if (!kept.partners.empty() && !kept.used) {  // found, never used: this pair turns too fast
      kept.partners.clear(), kept.margin = -1, kept.rest = kRest;
      return;
    }
    kept.used = false;
    kept.partners.resize(a_.hull->edges.size());
    for (std::size_t i = 0; i < kept.partners.size(); ++i) kept.partners[i] = partners(i);
    kept.turn = turn;
    kept.margin = least_margin();
    kept_ = &kept;
  }
  // The edges j of B whose arcs -b1 -> -b2 cross A's edge i's arc a1 -> a2 (bit j): each arc's great
  // circle separates the other's ends (the products of their sides are negative), and they cross on the
  // arcs, not opposite them. Only when usable(). The sides are taken as they are first needed, since the
  // search asks of only some of A's edges.
  std::uint64_t partners(std::size_t i) { return kept_ ? kept_->partners[i] : found(i); }

 private:
  std::uint64_t found(std::size_t i) {
    const auto [fa1, fa2] = a_.hull->edge_faces[i];
    face_sides(fa1), face_sides(fa2);
    std::uint64_t neg_a = 0, pos_a = 0;
    sides_of(Vec3(a_.arcs.x[i], a_.arcs.y[i], a_.arcs.z[i]), b_.normal_coordinates, neg_a, pos_a);
    std::uint64_t below1 = 0, below2 = 0, above1 = 0, above2 = 0;  // B's edges whose face 1 (2) is below
    for (std::uint64_t m = neg_a; m; m &= m - 1) {
      const int k = __builtin_ctzll(m);
      below1 |= first_b_[k], below2 |= second_b_[k];
    }
    for (std::uint64_t m = pos_a; m; m &= m - 1) {
      const int k = __builtin_ctzll(m);
      above1 |= first_b_[k], above2 |= second_b_[k];
    }
    const std::uint64_t straddle_a = (below1 & above2) | (above1 & below2);
    const std::uint64_t straddle_b = (neg_b_[fa1] & pos_b_[fa2]) | (pos_b_[fa1] & neg_b_[fa2]);
    const std::uint64_t on_arcs = (below1 & pos_b_[fa2]) | (above1 & neg_b_[fa2]);
    return straddle_a & straddle_b & on_arcs;
  }
  // Which of B's arcs A's face normal k lies below and above (n . arc = arc . n), once per k.
  void face_sides(int k) {
    const std::uint64_t bit = std::uint64_t{1} << k;
    if (sided_ & bit) return;
    sides_of(a_.world_normals[static_cast<std::size_t>(k)], b_.arcs, neg_b_[k], pos_b_[k]);
    sided_ |= bit;
  }
  // The least of |n . arc| / |arc| over every sign the crossings rest on (each face normal n of one body
  // against each arc of the other), less an allowance for the rounding of the sides and of the turn: a
  // relative turn by angle theta moves each by at most 2 sin(theta / 2) |arc|.
  double least_margin() const {
    constexpr double kRounding = 1e-11;
    double least = 1e300;
    auto against = [&](const Placed3::Coordinates& normals, const Placed3::Coordinates& arcs) {
      for (std::size_t j = 0; j < arcs.x.size(); ++j) {
        const Vec3 arc = arcs[j];
        const Two ax = two(arc.x()), ay = two(arc.y()), az = two(arc.z());
        Two low = two(1e300);
        std::size_t k = 0;
        for (; k + 2 <= normals.x.size(); k += 2) {
          const Two side = dots(ax, ay, az, normals, k);
          const Two size = side < two(0) ? -side : side;
          low = size < low ? size : low;
        }
        double nearest = std::min(low[0], low[1]);
        for (; k < normals.x.size(); ++k) nearest = std::min(nearest, std::abs(arc.dot(normals[k])));
        least = std::min(least, (nearest - kRounding) / arc.norm());
      }
    };
    against(b_.normal_coordinates, a_.arcs);
    against(a_.normal_coordinates, b_.arcs);
    return least - kRounding;
  }
  const Placed3 &a_, &b_;
  bool usable_;
  GaussCrossings* kept_ = nullptr;
  std::uint64_t sided_ = 0;  // A's faces whose neg_b_ and pos_b_ are set
  std::uint64_t neg_b_[64], pos_b_[64];
  const std::uint64_t *first_b_ = nullptr, *second_b_ = nullptr;  // B's edges by their faces (its hull's)
};

// A hint names its axis by kind (0: a face of A, 1: a face of B, 2: an edge pair) and index (the face,
// or edge of A * 4096 + edge of B), as Axis does.
constexpr int kHintKindShift = 20;
SeparatingHint hint_for(int kind, std::size_t index) {
  return static_cast<SeparatingHint>((kind << kHintKindShift) | static_cast<int>(index));
}

// The overlap of A and B on the axis a hint names, as the search would weigh it (edge pairs by 1.05):
// below zero when that axis separates them now, 1e300 for a hint that fits neither body. When they
// overlap on it, `on` is that axis as the search would have it for its best (the same bits).
double hinted_overlap(const Placed3& a, const Placed3& b, SeparatingHint hint, Axis& on) {
  const int kind = hint >> kHintKindShift;
  const std::size_t index = static_cast<std::size_t>(hint & ((1 << kHintKindShift) - 1));
  if (kind == 0 || kind == 1) {
    const std::size_t faces = (kind == 0 ? a : b).world_normals.size();
    if (index >= faces) return 1e300;
    return overlap_on_face(a, b, kind, index, on) ? on.overlap : -1;
  }
  const std::size_t i = index / 4096, j = index % 4096;
  if (kind != 2 || i >= a.hull->edges.size() || j >= b.hull->edges.size()) return 1e300;
  const auto& ea = a.hull->edges[i];
  const auto& eb = b.hull->edges[j];
  const Vec3 da = a.world_vertices[ea.second] - a.world_vertices[ea.first];
  const Vec3 db = b.world_vertices[eb.second] - b.world_vertices[eb.first];
  const Vec3 n = da.cross(db);
  if (n.squaredNorm() < 1e-12 * da.squaredNorm() * db.squaredNorm()) return 1e300;
  return overlap_on(a, b, n.normalized(), on, 2, static_cast<int>(index), 1.05) ? on.overlap : -1;
}

// Most axes of two touching grains are far from the line of their centres, and on those the grains
// overlap by nearly their widths. Each hull holds a ball of its inradius about its centre, so on unit
// axis n their overlap is at least that of the balls with the other's interval: an axis whose least
// overlap already exceeds an overlap found elsewhere (`limit`: the hinted axis's, then the search's best)
// can neither separate the grains nor be the first least one, and is not projected. The contacts are
// those of the full search to the bit. `slack` covers the rounding of the bound. On an edge pair's axis
// n (weighed by 1.05) the bound is rA + rB - |n . (xA - xB)|, with rA, rB the inradii.
struct AxisBound {
  double limit = 1e300, slack = 0;
  // On a face normal n of `owner`, whose own extent on it is [lo, hi]; `other` is the other hull.
  bool skips_face(double lo, double hi, const Vec3& n, const Placed3& other) const {
    return face_floor(lo, hi, n, other) > limit;
  }
  // The least overlap the inscribed ball allows on that face normal.
  double face_floor(double lo, double hi, const Vec3& n, const Placed3& other) const {
    const double c = n.dot(other.x);
    return std::min(hi - c, c - lo) + other.inradius - slack;
  }
  // What |n . (xA - xB)| must reach on an edge pair's unit axis n for it to be projected.
  double edge_need(const Placed3& a, const Placed3& b) const {
    return a.inradius + b.inradius - slack - limit / 1.05;
  }
};

}  // namespace

int sphere_hull(const Placed3& s, const Placed3& h, bool sphere_is_a, std::vector<ContactPoint3>& out) {
  if ((s.x - h.x).norm() >= s.radius + h.radius) return 0;
  int deepest = 0;
  double max_d = -1e300, best_gap = 1e300;
  Vec3 best = s.x;
  for (std::size_t f = 0; f < h.world_normals.size(); ++f) {
    const double d = h.world_normals[f].dot(s.x) - h.world_offsets[f];
    if (d > max_d) max_d = d, deepest = static_cast<int>(f);
    if (d > 0) {
      const Vec3 c = closest_on_face(h, static_cast<int>(f), s.x);
      if ((c - s.x).norm() < best_gap) best_gap = (c - s.x).norm(), best = c;
    }
  }
  Vec3 n;  // from the hull to the sphere
  double depth;
  if (max_d > 0) {
    if (best_gap >= s.radius || best_gap == 0) return 0;
    n = (s.x - best) / best_gap;
    depth = s.radius - best_gap;
  } else {  // the centre is inside the hull: push out through the nearest face
    n = h.world_normals[deepest];
    depth = s.radius - max_d;
    best = s.x - n * max_d;
  }
  out.push_back({best + n * (depth / 2), sphere_is_a ? n : Vec3(-n), depth, 0});
  return 1;
}

namespace {

// What the search saw of the axes that did not win, for a least axis to be kept (LeastAxis): the two
// lowest face overlaps projected (the lowest may be the winner), the lowest floor of the faces skipped,
// and each edge pair projected (its index and weighed overlap, in the order of the search).
struct SeenAxes {
  double face_low[2] = {1e300, 1e300};
  int face_id[2] = {-1, -1};  // kind * 64 + face
  double skipped_floor = 1e300;
  // The first kEdges edge pairs projected (any others are bounded by their floors, which hold too).
  static constexpr std::size_t kEdges = 32;
  struct Edge {
    int index;
    double overlap;
  } edges[kEdges];  // (left unset: filled as they come)
  std::size_t n_edges = 0;
  void edge(int index, double overlap) {
    if (n_edges < kEdges) edges[n_edges++] = Edge{index, overlap};
  }
  void face(const Axis& on) {
    const int id = on.kind * 64 + on.index;
    if (on.overlap < face_low[0])
      face_low[1] = face_low[0], face_id[1] = face_id[0], face_low[0] = on.overlap, face_id[0] = id;
    else if (on.overlap < face_low[1])
      face_low[1] = on.overlap, face_id[1] = id;
  }
  double other_faces(const Axis& best) const {
    const bool first_won = best.kind < 2 && face_id[0] == best.kind * 64 + best.index;
    return std::min(skipped_floor, first_won ? face_low[1] : face_low[0]);
  }
};

// The contacts of A and B given the least axis of their separating-axis test.
int contacts_on(const Placed3& a, const Placed3& b, const Axis& best, std::vector<ContactPoint3>& out) {
  if (best.kind == 0) return face_contacts(a, best.index, b, false, out);
  if (best.kind == 1) return face_contacts(b, best.index, a, true, out);
  // Edge-edge: among edge pairs parallel to the winning pair, the closest pair touches.
  const auto& ea = a.hull->edges;
  const auto& eb = b.hull->edges;
  const auto [i0, j0] = std::pair<int, int>{best.index / 4096, best.index % 4096};
  const Vec3 da0 = (a.world_vertices[ea[i0].second] - a.world_vertices[ea[i0].first]).normalized();
  const Vec3 db0 = (b.world_vertices[eb[j0].second] - b.world_vertices[eb[j0].first]).normalized();
  // Parallel: the unit edge's |cos| with the unit d0 at least 1 - 1e-9. An edge whose |cos| is clearly
  // below (under 0.99, far beyond any rounding) is passed over before its direction is normalised: most
  // edges are, and the test then gives the same answers for a fraction of the square roots.
  auto parallel = [](const Vec3& d, const Vec3& d0) {
    const double c = d.dot(d0);
    return c * c >= 0.9801 * d.squaredNorm() && std::abs(d.normalized().dot(d0)) >= 1 - 1e-9;
  };
  double gap_min = 1e300;
  Vec3 point = Vec3::Zero();
  int feature = 0;
  for (std::size_t i = 0; i < ea.size(); ++i) {
    if (!parallel(a.world_vertices[ea[i].second] - a.world_vertices[ea[i].first], da0)) continue;
    for (std::size_t j = 0; j < eb.size(); ++j) {
      if (!parallel(b.world_vertices[eb[j].second] - b.world_vertices[eb[j].first], db0)) continue;
      double gap;
      const Vec3 m = segment_midpoint(a.world_vertices[ea[i].first], a.world_vertices[ea[i].second],
                                      b.world_vertices[eb[j].first], b.world_vertices[eb[j].second], gap);
      if (gap < gap_min) gap_min = gap, point = m, feature = 200000 + static_cast<int>(i * 64 + j);
    }
  }
  out.push_back({point, best.n, best.overlap / 1.05, feature});
  return 1;
}

// Whether the kept least axis is still the least, its overlap now `on.overlap` (LeastAxis). It also asks
// that the grains overlap by clearly more than rounding on it: then every axis, the line of centres
// included, overlaps them, as the search would find.
bool least_holds(const Placed3& a, const Placed3& b, const GaussCrossings& kept, const Axis& on,
                 double slack) {
  const LeastAxis& l = kept.least;
  const Quat turn = a.q.conjugate() * b.q;
  if (!crossings_hold(kept, a, turn) || !(on.overlap > 2 * slack && on.overlap < 1e300)) return false;
  const double dp = (a.q.conjugate() * (b.x - a.x) - l.at).norm();
  const double s = 2 * (l.turn.conjugate() * turn).vec().norm();
  if (!(s <= l.span)) return false;
  const double need = on.overlap + slack;
  return l.faces - dp - l.face_lever * s > need &&
         l.edges + (l.edges_at_span - l.edges) * (s / l.span) - 1.05 * dp > need;
}

// Keeps the least axis `best` a search has just found among the kept crossings `kept`, with the bounds
// on every other axis (LeastAxis): the overlaps the search projected, and for the rest the floors of the
// inscribed balls (AxisBound). An edge pair of the crossings too nearly parallel to give an axis now
// could give one after a turn, from any direction: then nothing is kept.
void keep_least(const Placed3& a, const Placed3& b, MinkowskiEdgePairs& gauss, const SeenAxes& seen,
                const Axis& best, double slack, GaussCrossings& kept) {
  LeastAxis& l = kept.least;
  l.axis = kNoHint;
  if (static_cast<std::size_t>(best.index) >= (std::size_t{1} << kHintKindShift)) return;
  const Vec3 centres = a.x - b.x;
  l.at = a.q.conjugate() * (b.x - a.x);
  l.turn = a.q.conjugate() * b.q;
  l.faces = seen.other_faces(best);
  // A's faces: B's points move by dp and by the turn about B's centre. B's faces: their normals turn too,
  // against A's points and B's centre as far as |at| from A's.
  l.face_lever = std::max(b.radius, a.radius + l.at.norm());
  // While the crossings hold, the turn since they were found is under their margin, so the turn since
  // now under that plus the turn they had already made (2 sin(x / 2) is subadditive).
  l.span = kept.margin + 2 * (kept.turn.conjugate() * l.turn).vec().norm();
  const double reach = a.radius + b.radius + l.at.norm();
  double low = 1e300, low_at_span = 1e300;
  const auto& ea = a.hull->edges;
  const auto& eb = b.hull->edges;
  const std::vector<double>& la = a.hull->edge_lengths;
  const std::vector<double>& lb = b.hull->edge_lengths;
  std::size_t k = 0;  // the next projected edge pair in seen.edges
  for (std::size_t i = 0; i < ea.size(); ++i) {
    const std::uint64_t partners = gauss.partners(i);
    if (!partners) continue;
    const Vec3 da = a.world_vertices[ea[i].second] - a.world_vertices[ea[i].first];
    for (std::uint64_t m = partners; m; m &= m - 1) {
      const auto j = static_cast<std::size_t>(__builtin_ctzll(m));
      const int index = static_cast<int>(i * 4096 + j);
      while (k < seen.n_edges && seen.edges[k].index < index) ++k;
      if (best.kind == 2 && best.index == index) continue;
      const Vec3 db = b.world_vertices[eb[j].second] - b.world_vertices[eb[j].first];
      const Vec3 w = da.cross(db);
      const double ww = w.squaredNorm(), lengths = la[i] * lb[j];
      if (ww < 1e-12 * lengths * lengths) return;
      const double wn = std::sqrt(ww);
      // The unit axis w / |w| turns by at most 2 |da| |db| / |w| times s.
      const double lever = 2 * lengths / wn * reach + b.radius;
      const double o = k < seen.n_edges && seen.edges[k].index == index
                           ? seen.edges[k].overlap
                           : 1.05 * (a.inradius + b.inradius - slack - std::abs(w.dot(centres)) / wn);
      low = std::min(low, o), low_at_span = std::min(low_at_span, o - 1.05 * lever * l.span);
    }
  }
  l.edges = low, l.edges_at_span = low_at_span;
  l.axis = hint_for(best.kind, static_cast<std::size_t>(best.index));
}

}  // namespace

int hull_hull(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out, SeparatingHint* hint,
              GaussCrossings* crossings) {
  const Vec3 centres = a.x - b.x;
  if (centres.norm() >= a.radius + b.radius) return 0;
  AxisBound bound;
  bound.slack =
      1e-9 * (a.radius + b.radius) + 1e-13 * (a.x.lpNorm<Eigen::Infinity>() + b.x.lpNorm<Eigen::Infinity>());
  if (hint && *hint != kNoHint) {  // the axis that separated, or was least, the last time
    Axis on;
    bound.limit = hinted_overlap(a, b, *hint, on);
    if (bound.limit < 0) return 0;
    // Still the least of a touching pair: that axis alone (LeastAxis).
    if (crossings && crossings->least.axis == *hint && least_holds(a, b, *crossings, on, bound.slack)) {
      crossings->used = true;
      return contacts_on(a, b, on, out);
    }
  }
  // Apart: remember the axis that showed it, for the next call.
  auto apart_by = [&](int kind, std::size_t index) {
    if (hint) *hint = index < (std::size_t{1} << kHintKindShift) ? hint_for(kind, index) : kNoHint;
    return 0;
  };
  Axis best;
  // The line of centres first: it separates most pairs that are apart (in a resting bed of irregular
  // grains 59 % of those whose bounding spheres overlap), at the cost of one axis. It only finds sooner
  // what the axes below would find; it does not enter `best`.
  if (Axis unused; centres.squaredNorm() > 0 && !overlap_on(a, b, centres.normalized(), unused, 0, 0, 1.0))
    return 0;
  SeenAxes seen;
  for (int kind = 0; kind < 2; ++kind) {  // the face normals of A, then of B
    const Placed3& owner = kind == 0 ? a : b;
    const Placed3& other = kind == 0 ? b : a;
    for (std::size_t f = 0; f < owner.world_normals.size(); ++f) {
      const double floor =
          bound.face_floor(owner.face_lo[f], owner.face_hi[f], owner.world_normals[f], other);
      if (floor > bound.limit) {
        seen.skipped_floor = std::min(seen.skipped_floor, floor);
        continue;
      }
      Axis on;
      if (!overlap_on_face(a, b, kind, f, on)) return apart_by(kind, f);
      seen.face(on);
      if (on.overlap < best.overlap) best = on;
      bound.limit = std::min(bound.limit, best.overlap);
    }
  }
  const auto& ea = a.hull->edges;
  const auto& eb = b.hull->edges;
  MinkowskiEdgePairs gauss(a, b);
  if (crossings && gauss.usable()) gauss.keep_in(*crossings);
  const bool keeping = crossings && gauss.kept();  // a least axis found now can be kept
  // An edge pair's axis n is projected only if |n . (xA - xB)| reaches `need` (AxisBound). Every axis of
  // an edge with direction d is square to it, so an edge too nearly along the line of centres reaches it
  // on none, and is left out before its pairs are sought.
  const double cc = centres.squaredNorm();
  auto edge_reaches = [&](const Vec3& d, double need) {
    const double dd = d.squaredNorm(), dc = d.dot(centres);
    return need <= 0 || cc * dd - dc * dc >= need * need * dd;
  };
  // Whether B's edge j reaches the need the faces left (need0), asked only of the edges the Gauss map
  // pairs with some edge of A, once each (bit j of `asked`; of `reaching` when it does).
  const double need0 = bound.edge_need(a, b);
  std::uint64_t asked = 0, reaching = 0;
  auto b_reaching = [&](std::uint64_t among) {
    for (std::uint64_t m = among & ~asked; m; m &= m - 1) {
      const auto j = static_cast<std::size_t>(__builtin_ctzll(m));
      if (edge_reaches(b.world_vertices[eb[j].second] - b.world_vertices[eb[j].first], need0))
        reaching |= std::uint64_t{1} << j;
    }
    asked |= among;
    return among & reaching;
  };
  // Edge axes must beat the best face axis clearly, so resting face contacts do not flicker to edges.
  // false: the pair's axis separates the bodies. `need` follows the limit (a division, taken again only
  // when an axis lowers it rather than for every edge).
  double need = need0;
  auto edge_axis = [&](std::size_t i, const Vec3& da, std::size_t j) {
    const Vec3 db = b.world_vertices[eb[j].second] - b.world_vertices[eb[j].first];
    Vec3 n = da.cross(db);
    const double nn = n.squaredNorm();
    if (nn < 1e-12 * da.squaredNorm() * db.squaredNorm()) return true;  // parallel edges
    const double nc = n.dot(centres);
    if (need > 0 && nc * nc < need * need * nn) return true;  // cannot win, cannot separate
    n.normalize();
    const int index = static_cast<int>(i * 4096 + j);
    Axis on;
    if (!overlap_on(a, b, n, on, 2, index, 1.05)) return false;
    if (keeping) seen.edge(index, on.overlap);
    if (on.overlap < best.overlap) best = on;
    if (best.overlap < bound.limit) bound.limit = best.overlap, need = bound.edge_need(a, b);
    return true;
  };
  for (std::size_t i = 0; i < ea.size(); ++i) {
    // (An edge with no partners is passed over first where that costs only a look.)
    if (gauss.kept() && gauss.partners(i) == 0) continue;
    const Vec3 da = a.world_vertices[ea[i].second] - a.world_vertices[ea[i].first];
    if (!edge_reaches(da, need)) continue;
    if (gauss.usable()) {
      for (std::uint64_t m = b_reaching(gauss.partners(i)); m; m &= m - 1)
        if (const auto j = static_cast<std::size_t>(__builtin_ctzll(m)); !edge_axis(i, da, j))
          return apart_by(2, i * 4096 + j);
    } else {
      for (std::size_t j = 0; j < eb.size(); ++j)
        if (!edge_axis(i, da, j)) return apart_by(2, i * 4096 + j);
    }
  }
  // Touching: the least axis is the likeliest least one next time, and its overlap a tight limit.
  if (hint && static_cast<std::size_t>(best.index) < (std::size_t{1} << kHintKindShift))
    *hint = hint_for(best.kind, static_cast<std::size_t>(best.index));
  if (keeping) keep_least(a, b, gauss, seen, best, bound.slack, *crossings);
  return contacts_on(a, b, best, out);
}

int body_body(const Placed3& a, const Placed3& b, std::vector<ContactPoint3>& out, SeparatingHint* hint,
              GaussCrossings* crossings) {
  if (!a.hull && !b.hull) return sphere_sphere(a, b, out);
  if (!a.hull) return sphere_hull(a, b, true, out);
  if (!b.hull) return sphere_hull(b, a, false, out);
  return hull_hull(a, b, out, hint, crossings);
}

}  // namespace grainlab::dem
