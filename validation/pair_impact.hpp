#pragma once
// Two grains colliding at the Ch. III scale (r = 1 cm, k = 6e9 dyn/cm, restitution 0.85, mu 0.5): the
// normal and tangential restitution, rebound angle and spin each engine produces, beside the rigid-body
// model of Walton (sliding and sticking regimes).
#include <string>

namespace grainlab::validation {

struct PairImpactResult {
  double normal_restitution = 0;      // -(v_n after) / (v_n before) of the contact point
  double tangential_restitution = 0;  // -(v_t after) / (v_t before) of the contact point (Walton's beta)
  double rebound_angle_deg = 0;       // of the contact point's relative velocity from the normal, after
  double spin = 0;                    // of the moving grain after the impact (rad/s)
  double impact_angle_deg = 0;        // of the incoming relative velocity from the impact's normal
  double kinetic_ratio = 0;           // kinetic energy (with rotation) after / before
  double normal_turn_deg = 0;         // the impact's normal (line of centres at the deepest overlap)
                                      // against the line of centres at first touch
};

// Grain B (2-D disc, or 3-D sphere) moving at `speed` onto grain A at rest, the velocity making
// `angle_deg` with the line of centres at the moment of contact; no gravity. Everything is measured in
// the frame of the line of centres at the deepest overlap (a soft contact turns while it lasts).
PairImpactResult pair_impact(const std::string& engine, int dimension, double speed, double angle_deg);

// Walton's rigid-body tangential restitution when the contact slides throughout:
// beta = -1 + mu (1 + e)(1 + 1/K) cot(angle), K = I / (m r^2) (1/2 disc, 2/5 sphere). The contact
// slides throughout while this is below the sticking value beta0.
double walton_sliding_beta(double mu, double e, double inertia_factor, double angle_deg);
// Walton's model with sticking value beta0: beta = min(beta0, the sliding value).
double walton_beta(double mu, double e, double beta0, double inertia_factor, double angle_deg);
// Spin of the moving grain of an equal pair after an impact of tangential restitution beta, incoming
// tangential contact velocity vt (cm/s): -(1 + beta) vt / (2 r (1 + K)).
double rigid_spin_after(double beta, double vt, double radius, double inertia_factor);

}  // namespace grainlab::validation
