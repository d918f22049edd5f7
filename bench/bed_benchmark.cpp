#include "bed_benchmark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
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

namespace {
// Median of a sample (the middle one of an odd count, the upper middle of an even one).
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}
}  // namespace

// Under mpirun the bed is spread over the ranks (slabs along x); every rank times the same steps.
BedResult run_bed(const BedOptions& o) {
  const Scene scene = parse_scene(bed_scene_toml(o), "<bench bed>");
  const bool distributed = parallel::size() > 1;
  // (The bed is periodic in x over its nx columns: too few, and the world names its period, which here
  // is the command's --nx.)
  dem::World settled = [&] {
    try {
      return dem::World(scene, {distributed, o.balance_every, o.ranks_y});
    } catch (const InputError& e) {
      if (e.key() != "scene.periodic_x") throw;
      throw InputError({"--nx", 0}, std::to_string(o.nx), e.message());
    }
  }();
  for (int s = 0; s < o.settle_steps; ++s) settled.step();
  std::vector<double> seconds;
  BedResult r;
  for (int rep = 0; rep < o.repeats; ++rep) {
    dem::World w = settled;  // every repetition does identical work
    const dem::Diagnostics before = w.diagnostics();
    const double comm_before = w.rank_load().seconds_communication;
    parallel::barrier();
    const auto t0 = std::chrono::steady_clock::now();
    for (int s = 0; s < o.timed_steps; ++s) w.step();
    parallel::barrier();
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    seconds.push_back(sec);
    if (rep > 0) continue;
    const dem::Diagnostics& d = w.diagnostics();
    r.share_forces = (d.seconds_forces - before.seconds_forces) / sec;
    r.share_neighbors = (d.seconds_neighbors - before.seconds_neighbors) / sec;
    r.neighbor_rebuilds = static_cast<long>(d.neighbor_rebuilds - before.neighbor_rebuilds);
    const double comm = w.rank_load().seconds_communication - comm_before;
    const std::vector<double> per_rank =
        parallel::gather_all({comm, sec - comm, double(w.owned_count()),
                              double(w.particles().size() - w.owned_count()), double(w.memory_bytes())});
    double comm_sum = 0, compute_max = 0, compute_sum = 0, owned = 0, ghosts = 0, bytes = 0;
    for (std::size_t k = 0; k < per_rank.size(); k += 5) {
      comm_sum += per_rank[k], compute_sum += per_rank[k + 1];
      compute_max = std::max(compute_max, per_rank[k + 1]);
      owned += per_rank[k + 2], ghosts += per_rank[k + 3], bytes += per_rank[k + 4];
    }
    r.ranks = parallel::size();
    r.share_communication = comm_sum / r.ranks / sec;
    r.imbalance = compute_max / (compute_sum / r.ranks);
    r.ghosts = static_cast<long>(ghosts);
    r.particles = static_cast<long>(owned);
    r.bytes_per_particle = bytes / owned;
    r.contacts = static_cast<long>(w.count_contacts());
    const dem::Particles all = w.gather_particles();
    for (std::size_t i = 0; i < all.size(); ++i) r.mean_height += all.y[i] / all.size();
    r.kinetic_energy = w.energies().kinetic();
  }
  // The step time of a distributed run is the slowest rank's: take each repetition's longest.
  for (double& s : seconds) s = parallel::max_all(s);
  r.steps = o.timed_steps;
  r.median_seconds = median(seconds);
  r.min_seconds = *std::min_element(seconds.begin(), seconds.end());
  r.max_seconds = *std::max_element(seconds.begin(), seconds.end());
  r.particle_steps_per_second = r.particles * static_cast<double>(r.steps) / r.median_seconds;
  return r;
}

int run_bed_command(const BedOptions& o) {
  const bool speak = parallel::rank() == 0;
  if (speak)
    fmt::print(
        stderr,
        "bench bed: {} x {} discs (spacing {} cm, first row at y = {} cm), {} settling + {} timed steps "
        "x {} repeats, {}\n",
        o.nx, o.ny, o.spacing, o.first_row, o.settle_steps, o.timed_steps, o.repeats,
        o.frictionless ? "frictionless" : "with friction");
  const BedResult r = run_bed(o);
  if (!speak) return 0;
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
  if (r.ranks > 1) {
    fmt::print("MPI ranks            {} ({} ghosts in all)\n", r.ranks, r.ghosts);
    fmt::print("communication        {:.1f} % of the step time (mean over ranks, waiting included)\n",
               100 * r.share_communication);
    fmt::print("load imbalance       {:.3f} (slowest rank's compute time / mean)\n", r.imbalance);
  }
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
                        {"frictionless", o.frictionless},
                        {"ranks", r.ranks},
                        {"share_communication", r.share_communication},
                        {"imbalance", r.imbalance},
                        {"ghosts", r.ghosts},
                        {"seconds", {r.min_seconds, r.median_seconds, r.max_seconds}}};
    write_file_atomically(o.json, j.dump(2) + "\n");
  }
  return 0;
}

}  // namespace grainlab::bench
