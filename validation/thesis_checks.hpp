#pragma once
// The code checks of the thesis's Ch. II, as measurements that the `thesis-code` suite reports and
// the tests assert. Each builds its scene from TOML text, so the scene reader is exercised too.
#include <string>
#include <vector>

namespace grainlab::validation {

// Table 2.1: two r = 1 cm discs, 2-D density 2 g/cm^2, k_n = 5e6 dyn/cm, damping coefficient 1000 g/s,
// head-on at relative speed v (cm/s).
struct PairCollision {
  double restitution = 0;    // outgoing / incoming relative normal speed
  int steps_in_contact = 0;  // accepted steps that ended with the discs overlapping
  int rejected_steps = 0;
};
PairCollision table21_collision(double v, double tolerance);
double table21_predicted_restitution();  // eq. 2.2 with the reduced mass

// Spinning circle dropped on a fixed line (w = 500 1/s, mu = 0.01, r = 0.5 cm, v = 99.1 cm/s, m = 1.57 g).
struct SpinLoss {
  double rotational_energy_loss = 0;  // erg
  double predicted = 0;               // 2 mu v m r w
};
SpinLoss spinning_circle_loss(double tolerance);

// An elastic gas of discs in a box (or with no walls), integrated with velocity Verlet.
struct GasConservation {
  double relative_energy_drift = 0;  // |E_end - E_0| / E_0
  double max_relative_energy_error = 0;
  double momentum_error = 0;  // |P_end - P_0| / sum m|v| (no walls only)
  int steps = 0;
  std::vector<double> times, energies;  // sampled
};
GasConservation elastic_gas(int discs, int steps, bool walls, std::uint64_t seed, double dt = 2.5e-5);

// Fig. 2.11: 30 discs r = 0.5 cm and one r = 1 cm shaken in a gold-pan container.
struct Sorting {
  double cycles_to_top = -1;  // first shaking cycle after which the large disc stays above 90 % of the others
  double frequency = 12;
  std::vector<double> cycles, large_height_rank;  // fraction of small discs below the large one, per sample
  std::vector<double> large_height;
};
// realization 0: the discs on their grid; k > 0: each small disc moved by a seeded jitter (run k).
Sorting gold_pan_sorting(double cycles, bool friction, int realization = 0);
// Realizations 1..runs: each one's rise time (infinity if the large disc did not stay on top within
// `cycles`), their median, and the fraction that rose.
struct SortingEnsemble {
  std::vector<double> cycles_to_top;
  double median = 0, fraction_risen = 0;
};
SortingEnsemble gold_pan_ensemble(double cycles, bool friction, int runs);

}  // namespace grainlab::validation
