#include "collision.hpp"

#include <algorithm>

namespace grainlab::ripples::hybrid {

bool collide(Vec3& v1, Vec3& v2, double m1, double m2, const Vec3& n, const CollisionLaw& law) {
  const Vec3 v12 = v1 - v2;
  const double vn = v12.dot(n);
  if (vn <= 0) return false;  // separating or grazing: only approaching pairs collide
  const Vec3 normal = vn * n, tangential = v12 - normal;
  const double vt = tangential.norm();
  const double mu = vt > 0 ? std::max(0.0, 1 - 3.5 * law.friction * (1 + law.restitution) * vn / vt) : 0.0;
  // The impulse on 1 over the reduced mass: (1 + eps) along n, (2/7)(1 - mu) across it.
  const Vec3 change = (1 + law.restitution) * normal + (2.0 / 7.0) * (1 - mu) * tangential;
  const double total = m1 + m2;
  v1 -= (m2 / total) * change;
  v2 += (m1 / total) * change;
  return true;
}

}  // namespace grainlab::ripples::hybrid
