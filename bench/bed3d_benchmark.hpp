#pragma once
// `grainlab bench bed3d`: issue #15's 3-D benchmark, the same work as bench/bed3d.in for LAMMPS
// (gran/hooke/history): a simple-cubic lattice of spheres dropped inside a floor and four side planes,
// fixed dt, timed after settling.
#include <functional>
#include <string>

namespace grainlab::bench {

struct Bed3dOptions {
  int nx = 20, ny = 20, nz = 6;
  int settle_steps = 0, timed_steps = 2000, repeats = 3;
  std::string json;
  bool scene_only = false;  // print the scene (TOML) instead of timing it
  // A poured bed instead of the lattice: pour_to pours NX NY NZ spheres into the same box (untimed, for
  // pour_seconds of simulated time) and writes the bed, its spheres stopped where the pour leaves them,
  // as BASE.toml (a scene, which bed_scene then times) and BASE.data (LAMMPS read_data, for
  // bench/bed3d_data.in), so both codes start from the same state: the same positions, no velocity, no
  // spring loaded.
  std::string pour_to, bed_scene;
  double pour_seconds = 0.3;
  // Called as the pour goes on with (simulated seconds done, pour_seconds): a 100,000-sphere pour takes
  // the better part of an hour. Empty: nothing is called.
  std::function<void(double, double)> progress;
};

// The bed as a scene (TOML text), so it runs through the same reader as any user scene.
std::string bed3d_scene_toml(const Bed3dOptions& o);
// The poured bed's scene (materials and planes as the lattice's, one poured assembly) before the pour.
std::string poured_bed3d_scene_toml(const Bed3dOptions& o);
int run_bed3d_bench(const Bed3dOptions& o);

}  // namespace grainlab::bench
