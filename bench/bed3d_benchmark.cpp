#include "bed3d_benchmark.hpp"

#include <fmt/format.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "parallel.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::bench {

std::string bed3d_scene_toml(const Bed3dOptions& o) {
  // Issue #15's parameters: r = 1 cm, density 2.65, spacing 2.02 cm from (1.01, 1.01, 1.01), floor z = 0,
  // side planes x = 0, x = 2.02 NX, y = 0, y = 2.02 NY; k_n = k_t = 6e9, gamma_n = 4516 and
  // gamma_t = 2258 1/s on the reduced mass, mu = 0.5, Verlet dt = 1e-6 s.
  const double a = 2.02;
  std::string t = fmt::format(R"toml(
[scene]
name = "bench bed3d {nx} x {ny} x {nz}"
dimension = 3
duration = 1.0
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-6
[materials.grain]
k_n = 6e9
gamma_n = 4516
k_s = 6e9
gamma_s = 2258
mu = 0.5
)toml",
                              fmt::arg("nx", o.nx), fmt::arg("ny", o.ny), fmt::arg("nz", o.nz));
  for (int i = 0; i < o.nx; ++i)
    for (int j = 0; j < o.ny; ++j)
      for (int k = 0; k < o.nz; ++k)
        t += fmt::format(
            "[[bodies]]\nshape = \"sphere\"\nradius = 1.0\ndensity = 2.65\nposition = [{}, {}, {}]\n",
            1.01 + a * i, 1.01 + a * j, 1.01 + a * k);
  const std::string planes[5][2] = {{"[0, 0, 0]", "[0, 0, 1]"},
                                    {"[0, 0, 0]", "[1, 0, 0]"},
                                    {fmt::format("[{}, 0, 0]", a * o.nx), "[-1, 0, 0]"},
                                    {"[0, 0, 0]", "[0, 1, 0]"},
                                    {fmt::format("[0, {}, 0]", a * o.ny), "[0, -1, 0]"}};
  for (const auto& p : planes)
    t += fmt::format("[[walls]]\ntype = \"plane\"\npoint = {}\nnormal = {}\n", p[0], p[1]);
  return t;
}

namespace {
// Heap bytes in use (glibc's count of allocated blocks, small and mapped). The process's resident size
// would undercount what the world holds: the scene's TOML document for 100,000 bodies is parsed and freed
// before the world is built, and the world's arrays then reuse those pages without growing it.
double heap_in_use() {
  const struct mallinfo2 m = ::mallinfo2();
  return static_cast<double>(m.uordblks + m.hblkhd);
}
}  // namespace

int run_bed3d_bench(const Bed3dOptions& o) {
  if (o.scene_only) {
    fmt::print("{}", bed3d_scene_toml(o));
    return 0;
  }
  const Scene scene = parse_scene(bed3d_scene_toml(o), "<bench bed3d>");
  // Under mpirun the bed is spread over the ranks (slabs along x); the time is the slowest rank's.
  const int ranks = parallel::size();
  const double dt = 1e-6, before = heap_in_use();
  // Balanced as `grainlab run` balances (its default --balance-every 1000, and re-cuts by measured speed).
  dem::World3d settled(scene, dem::Decomposition{ranks > 1, dem::kBalanceEveryDefault, 1});
  settled.advance_to(o.settle_steps * dt);
  std::vector<double> memory{heap_in_use() - before};
  parallel::sum_all(memory);
  const double bytes = memory[0];
  const long n = static_cast<long>(settled.bodies().size());
  std::vector<double> seconds;
  dem::World3d last = settled;
  for (int rep = 0; rep < o.repeats; ++rep) {
    dem::World3d w = settled;  // every repetition does identical work
    parallel::barrier();
    const auto t0 = std::chrono::steady_clock::now();
    w.advance_to((o.settle_steps + o.timed_steps) * dt);
    seconds.push_back(
        parallel::max_all(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
    if (rep + 1 == o.repeats) last = w;
  }
  std::sort(seconds.begin(), seconds.end());
  const double median = seconds[seconds.size() / 2], rate = double(n) * o.timed_steps / median;
  double mean_z = 0;
  for (const auto& b : last.bodies()) mean_z += b.x.z() / double(n);  // (rank 0 holds them all)
  const auto e = last.energies();                                     // collective
  const double ke = e.kinetic_translational + e.kinetic_rotational;
  if (parallel::rank() != 0) return 0;
  fmt::print(
      "bed3d {} x {} x {} = {} spheres{}, {} settling + {} timed Verlet steps, median of {}: {:.3f} s, "
      "{:.4g} "
      "particle-steps/s, {:.0f} bytes per particle; mean height {:.6f} cm, kinetic energy {:.6g} erg\n",
      o.nx, o.ny, o.nz, n, ranks > 1 ? fmt::format(" on {} ranks", ranks) : "", o.settle_steps, o.timed_steps,
      o.repeats, median, rate, bytes / double(n), mean_z, ke);
  if (!o.json.empty())
    std::ofstream(o.json) << nlohmann::json{{"spheres", n},
                                            {"settle_steps", o.settle_steps},
                                            {"timed_steps", o.timed_steps},
                                            {"median_seconds", median},
                                            {"min_seconds", seconds.front()},
                                            {"max_seconds", seconds.back()},
                                            {"particle_steps_per_second", rate},
                                            {"ranks", ranks},
                                            {"bytes_per_particle", bytes / double(n)},
                                            {"mean_height", mean_z},
                                            {"kinetic_energy", ke}}
                                 .dump(2)
                          << "\n";
  return 0;
}

}  // namespace grainlab::bench
