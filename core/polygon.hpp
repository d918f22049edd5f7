#pragma once
// Geometry of convex polygons: mass properties and the overlap of two outlines. Used by the scene
// checks (initial overlaps) and by the native engine's narrow phase.
#include <vector>

#include "vec2.hpp"

namespace grainlab {

struct PolygonMass {
  double area = 0;
  Vec2 centroid{};
  double polar_moment_per_density = 0;  // second moment about the centroid, per unit density
};

PolygonMass polygon_mass(const std::vector<Vec2>& v);
bool is_convex_ccw(const std::vector<Vec2>& v);
double bounding_radius(const std::vector<Vec2>& v);  // about the origin

// A vertex of the overlap of two outlines, marked when it lies where the outlines cross.
struct OverlapVertex {
  Vec2 p;
  bool crossing = false;
};

// The overlap of two convex counter-clockwise polygons (Sutherland-Hodgman clipping of a by b).
std::vector<OverlapVertex> convex_overlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

// Points where a circle crosses a closed polygon outline.
std::vector<Vec2> circle_polygon_crossings(Vec2 centre, double radius, const std::vector<Vec2>& poly);
bool point_in_convex(Vec2 p, const std::vector<Vec2>& poly);

}  // namespace grainlab
