#pragma once
// The thesis's rebound model (Appendix III.1, eq. 3.A.1): an incident disc hits a single layer of evenly
// spaced bed discs that behave as two-body partners of effective mass m_beff. Up to two collisions are
// followed; a grain that would strike a third time, or that leaves downward, is "nabbed" (no outgoing
// momentum). Averages are over impact points uniform across the incoming stream, which weights each
// target by its exposed width.
#include <vector>

namespace grainlab::validation {

struct ReboundParams {
  double alpha_deg = 15;      // incident angle below the horizontal
  double radius_ratio = 1;    // r_i / r_b
  double mass_ratio = 0.5;    // m_i / m_beff
  double bed_gap = 0;         // Delta_b / r_b: surface gap between neighbouring bed discs
  double spin = 0;            // w_i r_i / v_i (counter-clockwise positive, as in eq. 3.A.1)
  double kappa_i = 0.5;       // I_i / (m_i r_i^2)
  double kappa_beff = 0.5;    // I_b / (m_beff r_b^2), see c1 below
  double restitution = 0.6;   // eps, the two-body normal restitution
  double sigma = 1;           // friction restitution: slip after = sigma x slip before
  int impact_points = 20000;  // quadrature points across one bed period
};

// Table 3.10's two parameter sets (CASE 2 stands for the simulations).
ReboundParams rebound_case(int which, double alpha_deg);

// One collision of eq. 3.A.1 in vector form. n: unit normal from the target's centre to the incident
// grain's; v, w: incident velocity and spin (in/out).
void rebound_collision(const ReboundParams& p, double nx, double ny, double& vx, double& vy, double& w);

struct ReboundSample {
  double eps_ix = 0, eps_iy = 0;  // 0 for nabbed grains
  double beta_deg = 0;            // first contact, from the vertical, positive on the upstream face
  double spin_out = 0;            // w_o r_i / v_i
  int collisions = 0;
  bool nabbed = false;
};

struct ReboundAverages {
  double eps_ix = 0, eps_iy = 0, eps_i = 0;  // means over all impacts (nabbed grains count as zero)
  double theta_i_deg = 0;                    // mean rebound angle from the vertical, rebounds only
  double beta_deg = 0;                       // mean first-contact angle
  double nabbed_fraction = 0;
  double below_one_fraction = 0;  // share of impacts with eps_iy < 1
  std::vector<ReboundSample> samples;
};

// Every impact point of one bed period, and their averages.
ReboundAverages rebound_model(const ReboundParams& p);

}  // namespace grainlab::validation
