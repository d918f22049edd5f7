#pragma once
// The thesis's triangular collision model (Ch. V section 3, Figs 5.17-5.20): ripples as triangles with a
// stoss slope beta and a lee slope alpha (the lee is the shadow line of impacts at alpha), each carried
// downstream by the flux Q over its crest. In the two-intercept form (spec [derived]) a ripple is its stoss
// intercept s and lee intercept l on the base, height H = (l - s) / K, K = cot beta + cot alpha. The crest
// flux erodes the exposed stoss and builds the lee: ds/dt = Q / (exposed stoss height), dl/dt = Q /
// (exposed lee height). When an upstream ripple's lee runs onto the downstream stoss, both are cut at the
// intersection, height y_i = (l_U - s_D) / K. Target transport: Q = q0; brink transport: Q = q0 / (exposed
// stoss length).
#include <string>
#include <vector>

namespace grainlab::ripples {

struct TriangleParams {
  double beta_deg = 5, alpha_deg = 10;  // Fig. 5.20
  std::string law = "target";           // "target" or "brink"
  double q0 = 1;
};

struct CollisionResult {
  double upstream_after = 0, downstream_after = 0;  // heights after they separate, in units of the
                                                    // downstream ripple's initial height
  double min_effective_height = 0;                  // min over the collision of (H_U - y_i) / H_U(0)
  double area_before = 0, area_after = 0;           // sum of H^2 (area / (K/2)): conserved
  double duration = 0;                       // time in contact (units of H_D0^2 / q0 for the target law)
  std::vector<double> t, h_up, h_down, y_i;  // the history, sampled
};

// An upstream ripple of height `ratio` x the downstream one's, starting a little behind it, until they
// separate. Throws std::invalid_argument for a bad law or ratio outside (0, 1).
CollisionResult triangle_collision(const TriangleParams& p, double ratio);

// Fig. 5.24: the largest ripple a merger of two ripples of height ratio `ratio` can make. Two ripples merge
// when the upstream one's smallest effective height during the collision (the mean of the target and
// brink curves of Fig. 5.20, times its height) falls below `critical_height` (cm): 0.23 cm for the
// statistical-fluctuation hypothesis, or reptation length x tan(alpha) for the reptation hypothesis (the
// shadow zone h_e cot(alpha) shorter than the reptation length). The largest downstream height that still
// merges, H_D = critical / (ratio x mean curve), makes a ripple of H_D sqrt(1 + ratio^2) (sand conserved),
// whose wavelength is its base K H (the triangles span shadow end to shadow end). Returns cm.
double limiting_wavelength(double ratio, double critical_height, double beta_deg = 5, double alpha_deg = 10);

// Speed of an isolated triangle of height H: Q / H.
double triangle_speed(const TriangleParams& p, double H);

}  // namespace grainlab::ripples
