#pragma once
// The thesis's contact law (eq. 2.3): linear normal spring with a dashpot on the reduced mass, and an
// incremental shear spring with a dashpot whose total is capped by mu f_n. Written once here and
// inlined into every contact kernel.
#include <algorithm>
#include <cmath>
#include <vector>

#include "polyhedron.hpp"
#include "scene.hpp"

namespace grainlab::dem {

inline double dot(const Vec3& a, const Vec3& b) {
  return a.dot(b);  // (a0 b0 + a1 b1) + a2 b2
}

// Damping expressed so that the force coefficient is c(m_eff) = coef + rate m_eff + rest sqrt(m_eff)
// (g/s): the three ways a scene may give it (rate, coefficient, restitution) without a branch.
struct DampingLaw {
  double coef = 0, rate = 0, rest = 0;
  double coefficient(double meff) const {
    double c = coef + rate * meff;
    if (rest != 0) c += rest * std::sqrt(meff);
    return c;
  }
};

struct ContactLaw {
  double k_n = 0, k_s = 0, mu = 0;
  DampingLaw normal, shear;
  bool clip_attractive = false;
};

DampingLaw damping_law(const Damping& d, double k_n);
ContactLaw contact_law(const Material& m, bool clip_attractive);
// The law between every pair of the scene's materials, indexed [a * n + b] with n = max(1, materials);
// pairs the scene does not define (they cannot touch) hold an empty law.
std::vector<ContactLaw> contact_law_table(const Scene& scene);

// eq. 2.2 with the force-coefficient convention: damping rate gamma = c / m_eff.
double restitution_from_damping(double k_n, double c, double meff);
// eq. 2.2 inverted: the force coefficient c giving restitution eps.
double damping_for_restitution(double k_n, double eps, double meff);
// Duration of a normal collision (half the damped period), for choosing steps.
double contact_duration(double k_n, double c, double meff);

// Normal force magnitude along n (positive = repulsive). vn = (v_i - v_j).n, negative when approaching.
inline double normal_force(const ContactLaw& L, double depth, double vn, double c_n) {
  const double f = L.k_n * depth - c_n * vn;
  return L.clip_attractive ? std::max(f, 0.0) : f;
}

// The cap on a shear force: a component keeps its sign, a vector its direction.
inline bool beyond_cap(double f, double cap) {
  return std::abs(f) > cap;
}
inline double to_cap(double f, double cap) {
  return std::copysign(cap, f);
}
template <class V>
bool beyond_cap(const V& f, double cap) {
  return dot(f, f) > cap * cap;
}
template <class V>
V to_cap(const V& f, double cap) {
  return f * (cap / std::sqrt(dot(f, f)));
}

// The shear spring of eq. 2.3, written once for both dimensions. T is the tangential quantity: a double
// in 2-D (the tangent is one direction, s = n rotated by -90 deg, so the spring turns with the contact by
// construction), a 3-vector in the tangent plane in 3-D (Vec3 or the sphere kernel's plain triple). `xi`
// holds the committed spring extension on entry and the new one on exit: xi += h v_t (the thesis's
// -k_s dt v_s increment), and when the total force exceeds mu f_n the spring's anchor slides so that the
// spring force equals the cap ("the spring force remains mu f_n").
template <class T>
T shear_force(const ContactLaw& L, double fn, const T& vt, double c_s, double h, T& xi) {
  xi = xi + h * vt;
  T f = -L.k_s * xi - c_s * vt;
  const double cap = L.mu * std::max(fn, 0.0);
  if (beyond_cap(f, cap)) {
    f = to_cap(f, cap);
    xi = -f / L.k_s;
  }
  return f;
}

// 3-D: the contact has turned since the spring was stored, so the spring is laid back into the tangent
// plane keeping its length (a projection alone would shorten it and leak stored force). A spring already
// in the plane would come back unchanged to the bit (the rescale is by sqrt(1)), so it is not turned: in a
// resting bed most springs are. (One square root, not three: hot in beds.)
template <class V>
void lay_into_tangent_plane(V& xi, const V& n) {
  if (const double along = dot(n, xi); along != 0) {
    const double len2 = dot(xi, xi);
    xi = xi - n * along;
    if (const double now2 = dot(xi, xi); now2 > 0) xi = xi * std::sqrt(len2 / now2);
  }
}

}  // namespace grainlab::dem
