#include "contact_events.hpp"

#include <algorithm>

namespace grainlab {

void ContactTracker::record(double t, double dt, const PairImpulses& step) {
  PairImpulses now;
  for (const auto& [pair, impulse] : step)
    now[{std::max(pair.first, pair.second), std::min(pair.first, pair.second)}] += impulse;
  for (auto it = open_.begin(); it != open_.end();) {
    if (now.count(it->first)) {
      ++it;
      continue;
    }
    it->second.open = false;
    done_.push_back(it->second);
    it = open_.erase(it);
  }
  for (const auto& [pair, impulse] : now) {
    auto [it, fresh] = open_.try_emplace(pair);
    ContactEvent& e = it->second;
    if (fresh) e = {pair.first, pair.second, t - dt, t, 0, 0, true};
    e.t_end = t;
    e.normal_impulse += impulse;
    e.peak_force = std::max(e.peak_force, dt > 0 ? impulse / dt : 0.0);
  }
}

std::vector<ContactEvent> ContactTracker::events() const {
  std::vector<ContactEvent> all = done_;
  for (const auto& [pair, e] : open_) all.push_back(e);
  return all;
}

}  // namespace grainlab
