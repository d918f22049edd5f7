#pragma once
// Time stepping shared by the 2-D and 3-D native worlds: the integrators' arithmetic, advancing to a time
// with fixed or adaptive steps, the thesis's step-size control for the predictor-corrector, and the step
// diagnostics.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "scene.hpp"
#include "world_types.hpp"

namespace grainlab::dem {

// The integrators' arithmetic, written once for both dimensions. V is one component (the 2-D engine keeps
// x, y and the spin in arrays of their own) or a 3-vector (Vec3, or the sphere kernel's plain triple); the
// operations and their order are the same either way, so a fix lands in both.

// Velocity Verlet: a half kick by the force (or torque) f on the inverse mass (or moment) inv, and a drift.
template <class V>
V half_kicked(const V& v, const V& f, double inv, double h) {
  return v + h * f * inv;
}
template <class V>
V drifted(const V& x, const V& v, double dt) {
  return x + dt * v;
}

// The thesis's first-order predictor-corrector (eq. 2.4): the velocity predicted from the one at the start
// of the previous step (or of this one) and the acceleration at this step's start over `back`, the
// position by the trapezoid rule, and the velocity corrected with the acceleration at the step's end.
template <class V>
V predicted(const V& v_back, const V& a0, double back) {
  return v_back + back * a0;
}
template <class V>
V trapezoid(const V& x0, const V& v0, const V& v1, double dt) {
  return x0 + dt * (v0 + v1) / 2;
}
template <class V>
V corrected(const V& v0, const V& a0, const V& a1, double dt) {
  return v0 + dt * (a0 + a1) / 2;
}
// One component's step error: how far the prediction missed, relative to the corrected velocity (or to
// its change over the step) plus a floor below which ratios are not trusted.
inline double step_error(double corrected_v, double predicted_v, double v0, bool relative_to_change,
                         double floor) {
  const double scale = relative_to_change ? std::abs(corrected_v - v0) : std::abs(corrected_v);
  return std::abs(corrected_v - predicted_v) / (scale + floor);
}

// Calls step() until time t reaches t_end. Fixed steps (Verlet) stop at the last step not beyond t_end
// (within a thousandth of a step); adaptive steps land exactly on t_end, and a short landing step does
// not shrink the next one. Adds the wall time to diag.
template <class Step>
void advance_steps(double& t, double& dt, double t_end, bool fixed_step, Diagnostics& diag, Step step) {
  const auto start = std::chrono::steady_clock::now();
  if (fixed_step) {
    while (t + dt * (1 - 1e-3) <= t_end) step();
  } else {
    while (t < t_end * (1 - 1e-14)) {
      const double natural = dt;
      const bool clamp = t + dt > t_end;
      if (clamp) dt = t_end - t;
      step();
      if (clamp) dt = std::max(dt, natural);
    }
  }
  diag.wall_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline void count_step(Diagnostics& diag, double taken) {
  ++diag.steps;
  diag.dt_last = taken;
  diag.dt_min_used = diag.steps == 1 ? taken : std::min(diag.dt_min_used, taken);
  diag.dt_max_used = std::max(diag.dt_max_used, taken);
}

// The predictor-corrector's step control (eq. 2.4): a step whose error exceeds the tolerance is
// rejected and halved (an error if that would go below dt_min); an accepted one grows by 20 % when the
// grown step should still pass (error ~ dt^2, so err * 1.2^2 <= tolerance). Returns whether the step of
// length dt is accepted and sets the next step length.
inline bool control_step(double err, double dt, double t, const Accuracy& acc, double& next_dt,
                         Diagnostics& diag) {
  if (err > acc.tolerance) {
    if (dt / 2 < acc.dt_min)
      throw std::runtime_error(fmt::format(
          "predictor-corrector step underflow at t = {:.6g} s: dt would fall below dt_min = {:.3g} s "
          "(error {:.3g} > tolerance {:.3g})",
          t, acc.dt_min, err, acc.tolerance));
    ++diag.rejected_steps;
    next_dt = dt / 2;
    return false;
  }
  if (err * 1.44 <= acc.tolerance) next_dt = std::min(dt * 1.2, acc.dt_max);
  return true;
}

}  // namespace grainlab::dem
