#include "contact_law.hpp"

namespace grainlab::dem {

// For the oscillator m x'' + c x' + k x = 0, eq. 2.2 reads eps = exp(-(c/m) T/4) with
// T = 2 pi / sqrt(k/m - (c/2m)^2). Writing L = -ln eps gives c = 2 L sqrt(k m) / sqrt(pi^2 + L^2).
double damping_for_restitution(double k_n, double eps, double meff) {
  if (eps <= 0) return 2 * std::sqrt(k_n * meff);  // the limit: critical damping, no rebound
  const double L = -std::log(eps);
  return 2 * L * std::sqrt(k_n * meff) / std::sqrt(M_PI * M_PI + L * L);
}

double restitution_from_damping(double k_n, double c, double meff) {
  const double g = c / meff;
  const double w2 = k_n / meff - g * g / 4;
  if (w2 <= 0) return 0;  // overdamped: no rebound in the linear model
  const double T = 2 * M_PI / std::sqrt(w2);
  return std::exp(-g * T / 4);
}

double contact_duration(double k_n, double c, double meff) {
  const double g = c / meff;
  const double w2 = k_n / meff - g * g / 4;
  return w2 > 0 ? M_PI / std::sqrt(w2) : M_PI * std::sqrt(meff / k_n);
}

DampingLaw damping_law(const Damping& d, double k_n) {
  DampingLaw law;
  switch (d.kind) {
    case Damping::Kind::None:
      break;
    case Damping::Kind::Rate:
      law.rate = d.value;
      break;
    case Damping::Kind::Coefficient:
      law.coef = d.value;
      break;
    case Damping::Kind::Restitution:
      law.rest = damping_for_restitution(k_n, d.value, 1.0);
      break;  // ~ sqrt(m)
  }
  return law;
}

ContactLaw contact_law(const Material& m, bool clip_attractive) {
  ContactLaw L;
  L.k_n = m.k_n;
  L.k_s = m.k_s;
  L.mu = m.mu;
  L.normal = damping_law(m.normal_damping, m.k_n);
  L.shear = damping_law(m.shear_damping, m.k_s);
  L.clip_attractive = clip_attractive;
  return L;
}

std::vector<ContactLaw> contact_law_table(const Scene& scene) {
  const int n = static_cast<int>(scene.materials.size());
  std::vector<ContactLaw> laws(static_cast<std::size_t>(std::max(1, n) * std::max(1, n)));
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b)
      if (a == b || scene.pair_materials.count({std::min(a, b), std::max(a, b)}))
        laws[a * n + b] = contact_law(scene.pair(a, b), scene.clip_attractive_normal_force);
  return laws;
}

}  // namespace grainlab::dem
