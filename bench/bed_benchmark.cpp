#include "bed_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "world.hpp"

namespace grainlab::bench {

std::string bed_scene_toml(const BedOptions& o) {
  // Parameters of bench/bed.in: spacing 2.02 cm, r = 1 cm, density 2 g/cm^2, lowest centres 1.5 cm
  // above the wall (y = 2.5), k_n = k_t = 6e9 dyn/cm, gamma_n = 4516 1/s, gamma_t = 2258 1/s on the
  // reduced mass, mu = 0.5, dt = 1e-6 s, neighbour skin 0.2 cm.
  const double spacing = o.spacing;
  return fmt::format(R"toml(
[scene]
name = "bench bed {nx} x {ny}"
duration = 1.0
periodic_x = [0.0, {period}]
effects = ["gravity", "normal_contact", {friction}"rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-6
skin = 0.2
[materials.grain]
k_n = 6e9
gamma_n = 4516
k_s = 6e9
gamma_s = 2258
mu = 0.5
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[assemblies]]
type = "lattice"
nx = {nx}
ny = {ny}
spacing = {spacing}
origin = [{half}, {y0}]
radius = 1.0
density = 2.0
)toml",
                     fmt::arg("nx", o.nx), fmt::arg("ny", o.ny), fmt::arg("period", o.nx * spacing),
                     fmt::arg("friction", o.frictionless ? "" : "\"friction\", "),
                     fmt::arg("spacing", spacing), fmt::arg("half", spacing / 2),
                     fmt::arg("y0", o.first_row));
}

BedResult run_bed(const BedOptions& o) {
  const Scene scene = parse_scene(bed_scene_toml(o), "<bench bed>");
  dem::World settled(scene);
  for (int s = 0; s < o.settle_steps; ++s) settled.step();
  std::vector<double> seconds;
  BedResult r;
  for (int rep = 0; rep < o.repeats; ++rep) {
    dem::World w = settled;  // every repetition does identical work
    const dem::Diagnostics before = w.diagnostics();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < o.timed_steps; ++s) w.step();
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds.push_back(sec);
    if (rep == 0) {
      const dem::Diagnostics& d = w.diagnostics();
      r.share_forces = (d.seconds_forces - before.seconds_forces) / sec;
      r.share_neighbors = (d.seconds_neighbors - before.seconds_neighbors) / sec;
      r.neighbor_rebuilds = static_cast<long>(d.neighbor_rebuilds - before.neighbor_rebuilds);
      r.bytes_per_particle = static_cast<double>(w.memory_bytes()) / w.particles().size();
      r.contacts = static_cast<long>(w.count_contacts());
      const dem::Particles& p = w.particles();
      for (std::size_t i = 0; i < p.size(); ++i) r.mean_height += p.y[i] / p.size();
      r.kinetic_energy = w.energies().kinetic();
    }
  }
  std::sort(seconds.begin(), seconds.end());
  r.particles = static_cast<long>(settled.particles().size());
  r.steps = o.timed_steps;
  r.median_seconds = seconds[seconds.size() / 2];
  r.min_seconds = seconds.front();
  r.max_seconds = seconds.back();
  r.particle_steps_per_second = r.particles * static_cast<double>(r.steps) / r.median_seconds;
  return r;
}

int run_bed_command(const BedOptions& o) {
  fmt::print(stderr,
             "bench bed: {} x {} discs (spacing {} cm, first row at y = {} cm), {} settling + {} timed steps "
             "x {} repeats, {}\n",
             o.nx, o.ny, o.spacing, o.first_row, o.settle_steps, o.timed_steps, o.repeats,
             o.frictionless ? "frictionless" : "with friction");
  const BedResult r = run_bed(o);
  fmt::print("particles            {}\n", r.particles);
  fmt::print("timed steps          {}\n", r.steps);
  fmt::print("seconds (median)     {:.4f}  (min {:.4f}, max {:.4f})\n", r.median_seconds, r.min_seconds,
             r.max_seconds);
  fmt::print("particle-steps/s     {:.4g}\n", r.particle_steps_per_second);
  fmt::print("bytes per particle   {:.0f}\n", r.bytes_per_particle);
  fmt::print("time in forces       {:.1f} %\n", 100 * r.share_forces);
  fmt::print("time in neighbours   {:.1f} %  ({} rebuilds)\n", 100 * r.share_neighbors, r.neighbor_rebuilds);
  fmt::print("contacts at end      {}\n", r.contacts);
  fmt::print("mean height (cm)     {:.6f}\n", r.mean_height);
  fmt::print("kinetic energy (erg) {:.6g}\n", r.kinetic_energy);
  if (!o.json.empty()) {
    nlohmann::json j = {{"particles", r.particles},
                        {"steps", r.steps},
                        {"median_seconds", r.median_seconds},
                        {"particle_steps_per_second", r.particle_steps_per_second},
                        {"bytes_per_particle", r.bytes_per_particle},
                        {"share_forces", r.share_forces},
                        {"share_neighbors", r.share_neighbors},
                        {"mean_height", r.mean_height},
                        {"kinetic_energy", r.kinetic_energy},
                        {"contacts", r.contacts},
                        {"frictionless", o.frictionless}};
    write_file_atomically(o.json, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace grainlab::bench
