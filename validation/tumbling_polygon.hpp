#pragma once
// The thesis's tumbling polygon (Ch. II section 4): a polygon dropped from rest onto an incline settles
// into bouncing, sliding, rolling or rest. Also the ideal pivot of a regular polygon (inelastic, no
// slip) that sets how a rolling polygon loses energy, and its terminal rolling speed.
#include <cstdint>
#include <string>
#include <vector>

#include "vec2.hpp"

namespace grainlab::validation {

struct TumblingShape {
  std::string name;
  std::vector<Vec2> vertices;  // counter-clockwise, cm
};
// The suite's three shapes: a 2 x 2 cm square, a 4 x 2 cm rectangle and the irregular hexagon of
// scenes/tumbling_hexagon.toml.
const std::vector<TumblingShape>& tumbling_shapes();

enum class Motion { Rest, Sliding, Rolling, Bouncing };
const char* motion_name(Motion m);

struct TumbleRun {
  Motion motion = Motion::Rest;
  double downslope_speed = 0;  // mean over the settled window (cm/s)
  double acceleration = 0;     // downslope velocity change / time, over the window or up to the last
                               // sample before it first falls below 1 cm/s; NaN if that is the first
  double turned = 0;           // |net rotation| over the window (rad)
  double airborne = 0;         // fraction of the window's samples with no vertex touching
};

struct Incline {
  double angle_deg = 30, mu = 0.5, restitution = 0.5;
};

// The settled window is the last kWindow seconds of a kDuration run, sampled every 0.01 s.
inline constexpr double kTumbleDuration = 4.0, kTumbleWindow = 1.0;

// Drop `index` of ensemble `seed`: the shape at rest, orientation uniform, its centroid four times its
// largest centre-to-vertex distance above the incline. The incline is the line y = 0 with gravity
// tilted by the incline angle, so downslope is +x and nothing ever runs off its end.
TumbleRun tumble(const std::string& engine, const TumblingShape& s, const Incline& in, std::uint64_t seed,
                 std::size_t index);

// Classifies a settled window (docs/validation.md): rolling if it turned through at least one vertex
// angle 2 pi / N; else bouncing if no vertex touched in at least 10 % of the samples; else at rest if
// it moved less than 1 cm/s on average (rocking or jitter in place counts as rest); else sliding.
Motion classify(double downslope_speed, double turned, double airborne, int vertices);

// Regular N-gon of circumradius R pivoting on one vertex at angular speed w- hits the plane with the
// next vertex B; B stops there (restitution e, no slip). The face AB makes the angle `tilt` with the
// plane at the impact (0: it lands flat, as when rolling on a plane). Returns w+/w- from rigid-body
// impulse mechanics; for e = 0 and tilt 0 it is 1 - (m R^2 / I_P)(1 - cos(2 pi / N)).
double pivot_ratio_rigid(int n, double restitution, double tilt = 0.0);
// The same impact simulated on `engine` in zero gravity (restitution e, friction mu large enough for
// no slip): w+/w-. `sets` are --set style overrides of the scene (e.g. the native shear damping).
double pivot_ratio_measured(const std::string& engine, int n, double restitution, double mu,
                            double tilt = 0.0, const std::vector<std::string>& sets = {});

// Steady rolling of a regular N-gon (circumradius R) down an incline by ideal inelastic no-slip pivots:
// each pivot a rigid pendulum, each impact keeping pivot_ratio_rigid(n, 0) of the spin.
struct IdealRolling {
  double speed = 0;        // mean downslope speed (cm/s); 0 if the spin after an impact cannot lift it
                           // over the next vertex
  bool lifts_off = false;  // the pivot would need the plane to pull (w^2 R > g cos): the model fails
};
IdealRolling ideal_rolling(int n, double circumradius, double incline_deg, double g);
// The terminal mean downslope speed of the same polygon rolling on `engine` (restitution e, friction
// mu), started rolling on its face: the mean over the last second of `duration`.
double measured_rolling_speed(const std::string& engine, int n, double circumradius, double incline_deg,
                              double restitution, double mu, double duration);

}  // namespace grainlab::validation
