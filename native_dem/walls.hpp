#pragma once
// Walls: fixed or prescribed-motion segments and infinite lines, of infinite mass.
#include "scene.hpp"

namespace grainlab::dem {

struct Wall {
  WallSpec spec;
  // Current geometry (updated by at(t)); for a line, a is a point on it and normal its front normal.
  Vec2 a{}, b{}, velocity{};
  Vec2 normal{};  // unit; for a segment, the left normal of a->b (the side polygons touch)

  void at(double t) {
    Vec2 shift{}, vel{};
    const Motion& m = spec.motion;
    if (m.active()) {
      const double om = 2 * M_PI * m.frequency;
      shift = {m.amplitude.x * std::sin(om * t + m.phase.x), m.amplitude.y * std::sin(om * t + m.phase.y)};
      vel = {m.amplitude.x * om * std::cos(om * t + m.phase.x),
             m.amplitude.y * om * std::cos(om * t + m.phase.y)};
    }
    a = spec.a + shift;
    velocity = vel;
    if (spec.kind == WallSpec::Kind::Segment) {
      b = spec.b + shift;
      const Vec2 d = b - a;
      normal = Vec2{-d.y, d.x} * (1 / norm(d));
    } else {
      normal = spec.b;
    }
  }
  double reach() const { return norm(spec.motion.amplitude); }  // how far the wall can move from rest
};

}  // namespace grainlab::dem
