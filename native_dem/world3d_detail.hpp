#pragma once
// Helpers shared by the 3-D engine's general path (world3d.cpp) and its sphere kernel
// (world3d_spheres.cpp).
#include <algorithm>
#include <cmath>

#include "contact_law.hpp"
#include "polyhedron.hpp"
#include "scene.hpp"
#include "world_types.hpp"

namespace grainlab::dem::detail3d {

// Orientation after turning at angular velocity w (world frame) for time dt.
inline Quat turned(const Quat& q, const Vec3& w, double dt) {
  if (w.x() == 0 && w.y() == 0 && w.z() == 0) return q;  // the identity turn: q stays as it was
  return (quat_from_rotation_vector(w * dt) * q).normalized();
}

// Gravity as the effects give it: off, as given, or reduced by buoyancy.
inline Vec3 effective_gravity(const Scene& s) {
  if (!s.effects.has(Effect::gravity)) return Vec3::Zero();
  const double keep = s.effects.has(Effect::buoyancy) ? 1 - s.fluid.density / s.fluid.grain_density : 1.0;
  return s.gravity3d * keep;
}

// The shear force of a contact with normal n, tangential velocity vt and normal force fn, from the spring
// xi stored at the last step (zero: a new contact), which is updated in place: laid back into the tangent
// plane, then the law shared with 2-D (contact_law.hpp).
inline Vec3 shear_force(const ContactLaw& law, Vec3& xi, const Vec3& n, const Vec3& vt, double h, double meff,
                        double fn) {
  lay_into_tangent_plane(xi, n);
  return dem::shear_force(law, fn, vt, law.shear.coefficient(meff), h, xi);
}

}  // namespace grainlab::dem::detail3d
