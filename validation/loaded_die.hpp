#pragma once
// The thesis's loaded 2-D die thrown onto a plane (Ch. II section 4): a square of half-side 1 cm whose
// centre of mass is moved a fraction f of the way to a corner, thrown with random orientation, height,
// speed and spin, followed until it is captured by one face.
#include <cstdint>
#include <string>
#include <vector>

namespace grainlab::validation {

struct Die2d {
  double f = 0;      // loading: centre of mass at (f, f) cm from the centre of the 2 x 2 cm square
  double eps = 0.7;  // die-plane restitution
  double mu = 0.8;   // die-plane friction (the model assumes the die rolls rather than slides)
};

// The scene of one throw (TOML). Faces, counter-clockwise from the bottom one as written: 0 (y = -1) and
// 3 (x = -1) are the high faces (far from the centre of mass), 1 (x = +1) and 2 (y = +1) the low faces.
std::string die_scene_2d(const Die2d& die, double angle, double height, double vx, double spin);

struct DieThrow {
  int face_down = -1;  // 0..3, or -1 if not captured within the time limit
  double time = 0;     // when it was captured (s)
  bool high_face_up() const { return face_down == 1 || face_down == 2; }
};

// Throw number `index` of the ensemble `seed` on `engine`. Initial conditions come from Rng(seed, index):
// orientation uniform in [0, 2 pi), centre of mass 3-5 cm above the plane, horizontal speed within
// +-50 cm/s, spin within +-20 rad/s. Captured: the energy above the rest state of the face the die is
// over is below half the lowest barrier out of that face's well, so (energy not rising) it can no
// longer tip to another face; docs/validation.md explains why this is exact.
// `sets` are --set style overrides of the scene (e.g. the native shear spring), applied after the
// engine's accuracy.
DieThrow throw_die_2d(const std::string& engine, const Die2d& die, std::uint64_t seed, std::size_t index,
                      const std::vector<std::string>& sets = {});

}  // namespace grainlab::validation

namespace grainlab::validation {

// A cube of half-side 1 cm (density 2 g/cm^3) whose centre of mass sits at `com` from its centre,
// optionally with its own inertia tensor (about the centre of mass, body axes; empty: the uniform cube's
// moved by the parallel-axis theorem) and mass (0: density x volume).
struct Die3d {
  double com[3] = {0, 0, 0};
  double inertia[9] = {};  // all zero: from the geometry
  double mass = 0;
  double eps = 0.5, mu = 0.8;
};

// The drilled ("Monopoly") die: 21 pips of depth 0.06 cm and radius 0.15 cm (a 2 cm die) removed from
// the faces, value v on the face whose outward normal is face_normal(v); returns its centre of mass,
// inertia and mass (pips as removed cylinders).
Die3d drilled_die(double eps, double mu);

// Value on the face with outward body normal n (1 on -z, 6 on +z, 2 on -y, 5 on +y, 3 on -x, 4 on +x:
// opposite faces sum to 7).
int die_value(double nx, double ny, double nz);

struct DieThrow3d {
  int value_up = 0;  // 1..6, 0 if not captured within the time limit
  double time = 0;
};

// Throw `index` of ensemble `seed` onto the plane z = 0: uniformly random orientation, centre of mass
// 3-5 cm up, horizontal velocity within +-50 cm/s per axis, spin within +-20 rad/s per axis. Captured
// as in 2-D: the energy above the rest state of the face the downward vertical through the centre of
// mass leaves by is below half the lowest barrier (an edge) out of that face.
DieThrow3d throw_die_3d(const std::string& engine, const Die3d& die, std::uint64_t seed, std::size_t index);

}  // namespace grainlab::validation
