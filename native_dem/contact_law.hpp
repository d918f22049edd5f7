#pragma once
// The thesis's contact law (eq. 2.3): linear normal spring with a dashpot on the reduced mass, and an
// incremental shear spring with a dashpot whose total is capped by mu f_n. Written once here and
// inlined into every contact kernel.
#include <algorithm>
#include <cmath>
#include <vector>

#include "scene.hpp"

namespace grainlab::dem {

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

// Shear force along s. `xi` holds the committed spring extension on entry and the new one on exit:
// xi += h vs (the thesis's -k_s dt v_s increment), and when the total exceeds mu f_n the spring's
// anchor slides so that the spring force equals the cap ("the spring force remains mu f_n").
inline double shear_force(const ContactLaw& L, double fn, double vs, double c_s, double h, double& xi) {
  xi += h * vs;
  double f = -L.k_s * xi - c_s * vs;
  const double cap = L.mu * std::max(fn, 0.0);
  if (std::abs(f) > cap) {
    f = std::copysign(cap, f);
    xi = -f / L.k_s;
  }
  return f;
}

}  // namespace grainlab::dem
