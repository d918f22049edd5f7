#pragma once
// Contact geometry: where two bodies (or a body and a wall) touch, along which normal, how deep.
#include <vector>

#include "polygon.hpp"
#include "walls.hpp"

namespace grainlab::dem {

struct ContactGeometry {
  Vec2 normal{};          // unit, from j (or the wall) towards i
  double depth = 0;       // overlap along the normal
  Vec2 arm_i{}, arm_j{};  // contact point relative to the centres of mass of i and j
};

struct BodyPose {
  Vec2 centre{};
  double angle = 0;
  double radius = 0;                            // disc radius or polygon bounding radius
  const std::vector<Vec2>* vertices = nullptr;  // null for a disc
};

// Disc against a wall. For a segment, the contact is with the nearest point, so past an end point the
// end point itself penetrates the disc (the thesis's end-point rule: no force jump off an edge).
// Segments act on discs from either side; lines from their front side only.
bool disc_wall_contact(Vec2 centre, double radius, const Wall& wall, ContactGeometry& c);

// Vertex v of a polygon against a wall (contacts at the polygon's vertices, as in the thesis). A
// segment is touched from its front (left of from->to) within its span.
bool vertex_wall_contact(const BodyPose& body, std::size_t v, const Wall& wall, ContactGeometry& c);

// Polygon-polygon and polygon-disc: the contact line joins the two crossing points of the outlines
// furthest apart; the normal is perpendicular to it and the depth is the width of the overlap along
// the normal (equal to the plain overlap for two discs, a vertex in a face, or a disc on a face).
// Disc-disc pairs are handled by the fast kernel, not here. Scratch vectors avoid allocation.
bool body_body_contact(const BodyPose& a, const BodyPose& b, ContactGeometry& c, std::vector<Vec2>& scratch_a,
                       std::vector<Vec2>& scratch_b);

}  // namespace grainlab::dem
