#pragma once
// `grainlab bench bed3d`: issue #15's 3-D benchmark, the same work as bench/bed3d.in for LAMMPS
// (gran/hooke/history): a simple-cubic lattice of spheres dropped inside a floor and four side planes,
// fixed dt, timed after settling.
#include <string>

namespace grainlab::bench {

struct Bed3dOptions {
  int nx = 20, ny = 20, nz = 6;
  int settle_steps = 0, timed_steps = 2000, repeats = 3;
  std::string json;
  bool scene_only = false;  // print the scene (TOML) instead of timing it
};

// The bed as a scene (TOML text), so it runs through the same reader as any user scene.
std::string bed3d_scene_toml(const Bed3dOptions& o);
int run_bed3d_bench(const Bed3dOptions& o);

}  // namespace grainlab::bench
