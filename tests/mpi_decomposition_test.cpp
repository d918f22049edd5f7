// Run under mpirun by ctest (1, 2 and 3 ranks): the distributed native engine gives, bit for bit, the
// serial run's positions, velocities, spins and energies:
//   - scenes/parallel_bed.toml, 5,000 discs, 10^4 Verlet steps (periodic in x, particles migrate);
//   - the same bed in a box of walls with the adaptive predictor-corrector (step size agreed by all);
//   - both again on a grid of ranks (cuts along y too).
// The bed is chaotic; so that this test can fail, rank 0 also shows that moving one disc by 1e-12 cm
// changes the end state.
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <cstring>

#include "h5_input.hpp"
#include "mpi_test_start.hpp"
#include "parallel.hpp"
#include "world.hpp"

using namespace grainlab;

namespace {

struct Difference {
  std::size_t mismatched = 0;
  double largest = 0;
};

Difference compare(const dem::Particles& a, const dem::Particles& b) {
  Difference d;
  if (a.size() != b.size()) return {a.size() + b.size(), INFINITY};
  for (std::size_t i = 0; i < a.size(); ++i)
    for (auto f : {&dem::Particles::x, &dem::Particles::y, &dem::Particles::th, &dem::Particles::vx,
                   &dem::Particles::vy, &dem::Particles::w}) {
      const double u = (a.*f)[i], v = (b.*f)[i];
      if (std::memcmp(&u, &v, sizeof u) != 0 || a.id[i] != b.id[i]) {
        ++d.mismatched;
        d.largest = std::max(d.largest, std::abs(u - v));
      }
    }
  return d;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// A world that runs steps/2, writes its state to a checkpoint file, is replaced by a fresh world that
// reads the file on every rank, and runs the other half.
dem::World interrupted_and_restarted(const Scene& scene, int steps, const std::string& file,
                                     dem::Decomposition how) {
  dem::World first(scene, how);
  for (int s = 0; s < steps / 2; ++s) first.step();
  const dem::WorldState saved = first.save_state();
  if (parallel::rank() == 0)
    write_sample_tables(file, dem::state_tables(saved, "state/"), {{"kind", "test"}});
  parallel::barrier();
  const TableFile read = read_sample_tables(file, dem::state_table_columns("state/"));
  dem::World second(scene, how);
  second.restore_state(dem::state_from_tables(read.tables, "state/"));
  for (int s = steps / 2; s < steps; ++s) second.step();
  return second;
}

// Runs `steps` steps distributed (straight through, and interrupted by a checkpoint halfway) and (on
// rank 0) serially; returns the number of failures.
int check(const std::string& name, const Scene& scene, int steps, bool perturb_check, int ranks_y = 1) {
  const dem::Decomposition how{true, 500, ranks_y};
  dem::World distributed(scene, how);
  for (int s = 0; s < steps; ++s) distributed.step();
  const std::string file = fmt::format("decomposition-checkpoint-{}.h5", parallel::size());
  const dem::World restarted = interrupted_and_restarted(scene, steps, file, how);
  const dem::Particles after_restart = restarted.gather_particles();
  const dem::Energies e_restart = restarted.energies();
  const dem::Energies e = distributed.energies();
  const std::size_t contacts = distributed.count_contacts();
  const dem::Particles all = distributed.gather_particles();
  if (parallel::rank() != 0) return 0;
  dem::World serial(scene);
  for (int s = 0; s < steps; ++s) serial.step();
  const dem::Particles reference = serial.gather_particles();
  const Difference d = compare(all, reference);
  const dem::Energies es = serial.energies();
  const bool energies_same = same_bits(e.total(), es.total()) && same_bits(e.elastic, es.elastic);
  int failures = 0;
  const Difference r = compare(after_restart, reference);
  if (r.mismatched || !same_bits(e_restart.total(), es.total()) || restarted.time() != serial.time() ||
      restarted.diagnostics().steps != serial.diagnostics().steps) {
    fmt::print(stderr,
               "{} on {} ranks, restarted from a checkpoint at step {}: {} values differ (largest {:.3g})\n",
               name, parallel::size(), steps / 2, r.mismatched, r.largest);
    ++failures;
  } else {
    fmt::print("  interrupted at step {}, restarted from {}: bitwise identical\n", steps / 2, file);
  }
  if (d.mismatched || !energies_same || contacts != serial.count_contacts() ||
      distributed.time() != serial.time()) {
    fmt::print(stderr,
               "{} on {} ranks: {} values differ from the serial run (largest {:.3g}); energy {} vs {}; "
               "contacts {} vs {}; t {} vs {}\n",
               name, parallel::size(), d.mismatched, d.largest, e.total(), es.total(), contacts,
               serial.count_contacts(), distributed.time(), serial.time());
    ++failures;
  }
  fmt::print("{}: {} discs, {} steps (t = {:.6g} s, {} rejected), {} contacts, {} ranks ({} re-splits): {}\n",
             name, reference.size(), steps, serial.time(), serial.diagnostics().rejected_steps, contacts,
             parallel::size(), distributed.rank_load().balances,
             failures ? "MISMATCH" : "bitwise identical to the serial run");
  if (perturb_check) {
    Scene moved = scene;
    dem::World nudged(moved);
    nudged.particles().x[0] += 1e-12;
    for (int s = 0; s < steps; ++s) nudged.step();
    const Difference c = compare(nudged.gather_particles(), reference);
    fmt::print("  moving one disc by 1e-12 cm changes {} of the {} values\n", c.mismatched,
               6 * reference.size());
    if (c.mismatched == 0) {
      fmt::print(stderr, "the bed is not sensitive to a 1e-12 cm nudge: this test could not fail\n");
      ++failures;
    }
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  int failures = testing::start_mpi_test(argc, argv);
  const std::string scene_path = argc > 2 ? argv[2] : "scenes/parallel_bed.toml";
  try {
    failures += check("parallel bed, Verlet", load_scene(scene_path), 10000, parallel::size() == 1);
    // The bed between two side walls with the adaptive predictor-corrector: 1,000 discs, 2,000 steps.
    const Scene boxed = parse_scene(R"toml(
[scene]
name = "walled bed"
duration = 1.0
seed = 3
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "predictor-corrector"
dt = 1e-5
[materials.sand]
k_n = 1.0e7
restitution = 0.6
k_s = 1.0e7
mu = 0.5
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [1.0, 0.0]
[[walls]]
type = "line"
point = [81.0, 0.0]
normal = [-1.0, 0.0]
[[assemblies]]
type = "lattice"
nx = 40
ny = 25
spacing = 2.02
origin = [1.01, 1.2]
velocity = [30.0, -150.0]
density = 2.0
[assemblies.radius_distribution]
kind = "uniform"
min = 0.7
max = 1.0
)toml",
                                    "<walled bed>");
    failures += check("walled bed, predictor-corrector", boxed, 2000, false);
    // A saltation bed under a wind the grains slow down (effect wind_drag): the wind is rebuilt from
    // fixed-point drag tallies summed over the ranks, so it too must be bitwise the serial one.
    const Scene windy = parse_scene(R"toml(
[scene]
name = "saltation bed"
duration = 1.0
seed = 18
periodic_x = [0.0, 3.0]
effects = ["gravity", "normal_contact", "friction", "rotation", "wind_drag", "buoyancy"]
[accuracy]
integrator = "verlet"
dt = 1e-6
[materials.sand]
k_n = 2.0e5
restitution = 0.9
k_s = 1.0e5
mu = 0.5
[fluid]
grain_density = 2.65
[wind]
u_star = 40.0
update_interval = 2e-4
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[assemblies]]
type = "lattice"
nx = 100
ny = 6
spacing = 0.03
origin = [0.015, 0.015]
sphere_density = 2.65
[assemblies.radius_distribution]
kind = "uniform"
min = 0.010625
max = 0.014375
[[assemblies]]
type = "lattice"
nx = 12
ny = 1
spacing = 0.24
origin = [0.12, 0.5]
sphere_density = 2.65
radius = 0.0125
velocity = [100.0, 0.0]
)toml",
                                    "<saltation bed>");
    failures += check("saltation bed, wind_drag", windy, 20000, parallel::size() == 1);
    // A grid of ranks: cuts along y as well (on 2 or 3 ranks, rows only; on 4, 2 x 2).
    if (parallel::size() > 1) {
      const int rows = parallel::size() % 2 == 0 && parallel::size() >= 4 ? 2 : parallel::size();
      const std::string grid = fmt::format(", {} x {} grid", parallel::size() / rows, rows);
      failures += check("parallel bed, Verlet" + grid, load_scene(scene_path), 4000, false, rows);
      failures += check("walled bed, predictor-corrector" + grid, boxed, 2000, false, rows);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "rank {}: {}\n", parallel::rank(), e.what());
    ++failures;
  }
  parallel::finalize();
  return failures ? 1 : 0;
}
