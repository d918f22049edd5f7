#pragma once
// Contact events: when two bodies (or a body and a wall) start and stop touching, and the normal impulse
// and peak normal force between them. Restitution, rebound and ejecta are measured from these. Every
// engine reports, after each step, the normal impulse each touching pair received in that step; the
// tracker turns the stream into events.
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace grainlab {

struct ContactEvent {
  // Body ids, body_a > body_b; a wall (or plane) k is -1 - k, so it is always body_b.
  std::int64_t body_a = 0, body_b = 0;
  double t_begin = 0;  // start of the first step with a normal impulse
  double t_end = 0;    // end of the last step with one (the latest step while still open)
  // Integral of the normal force over the contact (g cm/s in cgs). For soft contacts it includes the
  // dashpot's pull at the end of a contact when the scene does not clip attractive forces.
  double normal_impulse = 0;
  double peak_force = 0;  // largest step-mean normal force
  bool open = false;      // still touching at the last recorded step
};

using PairImpulses = std::map<std::pair<std::int64_t, std::int64_t>, double>;

class ContactTracker {
 public:
  // The listed pairs touched during the step (t - dt, t] and received the normal impulse shown (pairs in
  // either order); a pair not listed has separated.
  void record(double t, double dt, const PairImpulses& step);
  // Finished events in the order they ended, then the open ones.
  std::vector<ContactEvent> events() const;

 private:
  std::map<std::pair<std::int64_t, std::int64_t>, ContactEvent> open_;
  std::vector<ContactEvent> done_;
};

}  // namespace grainlab
