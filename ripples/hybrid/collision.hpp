#pragma once
// Mid-air collisions of airborne grains in the 3-D hybrid ripple model (Huo et al. 2021, after Brilliantov
// & Poschel): instantaneous hard-sphere events without rotation, a normal restitution and a Coulomb-limited
// tangential part. docs/hybrid.md "The 3-D hybrid model"; spec frontiers-3d-ripples.md section 1.
#include <Eigen/Core>

namespace grainlab::ripples::hybrid {

using Vec3 = Eigen::Vector3d;

struct CollisionLaw {
  double restitution = 0.9;  // eps, normal
  double friction = 0.4;     // C_f, Coulomb coefficient of the tangential impulse
};

// Collides grains 1 and 2 (masses m1, m2; n the unit vector from 1's centre to 2's) if they approach
// along n, changing v1 and v2; returns whether they did. Momentum is conserved exactly; the normal
// relative speed drops by eps, and the tangential one by (2/7)(1 - mu) with
// mu = max(0, 1 - (7/2) C_f (1 + eps) |v_n| / |v_t|): (2/7) is a sphere that rolls off without slipping,
// mu > 0 where the Coulomb limit makes it slide.
bool collide(Vec3& v1, Vec3& v2, double m1, double m2, const Vec3& n, const CollisionLaw& law);

}  // namespace grainlab::ripples::hybrid
