#include "bed3d_benchmark.hpp"

#include <fmt/format.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "parallel.hpp"
#include "scene.hpp"
#include "world3d.hpp"

namespace grainlab::bench {

namespace {
constexpr double kSpacing = 2.02;  // cm, the lattice's; the box is NX and NY spacings wide

// Issue #15's parameters: r = 1 cm, density 2.65, floor z = 0, side planes x = 0, x = 2.02 NX, y = 0,
// y = 2.02 NY; k_n = k_t = 6e9, gamma_n = 4516 and gamma_t = 2258 1/s on the reduced mass, mu = 0.5,
// Verlet dt = 1e-6 s. The scene's head and its planes; the bodies come between.
std::string bed3d_head(const std::string& name) {
  return fmt::format(R"toml(
[scene]
name = "{}"
dimension = 3
duration = 1.0
seed = 1
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
                     name);
}

std::string bed3d_planes(const Bed3dOptions& o) {
  const double a = kSpacing;
  const std::string planes[5][2] = {{"[0, 0, 0]", "[0, 0, 1]"},
                                    {"[0, 0, 0]", "[1, 0, 0]"},
                                    {fmt::format("[{}, 0, 0]", a * o.nx), "[-1, 0, 0]"},
                                    {"[0, 0, 0]", "[0, 1, 0]"},
                                    {fmt::format("[0, {}, 0]", a * o.ny), "[0, -1, 0]"}};
  std::string t;
  for (const auto& p : planes)
    t += fmt::format("[[walls]]\ntype = \"plane\"\npoint = {}\nnormal = {}\n", p[0], p[1]);
  return t;
}

std::string sphere_toml(const Vec3& x) {  // ({} prints the shortest text that reads back to the same double)
  return fmt::format(
      "[[bodies]]\nshape = \"sphere\"\nradius = 1.0\ndensity = 2.65\nposition = [{}, {}, {}]\n", x.x(), x.y(),
      x.z());
}
}  // namespace

std::string bed3d_scene_toml(const Bed3dOptions& o) {
  // The lattice: spacing 2.02 cm from (1.01, 1.01, 1.01).
  const double a = kSpacing;
  std::string t = bed3d_head(fmt::format("bench bed3d {} x {} x {}", o.nx, o.ny, o.nz));
  for (int i = 0; i < o.nx; ++i)
    for (int j = 0; j < o.ny; ++j)
      for (int k = 0; k < o.nz; ++k) t += sphere_toml(Vec3(1.01 + a * i, 1.01 + a * j, 1.01 + a * k));
  return t + bed3d_planes(o);
}

std::string poured_bed3d_scene_toml(const Bed3dOptions& o) {
  return bed3d_head(fmt::format("bench bed3d poured {} x {} x {}", o.nx, o.ny, o.nz)) + bed3d_planes(o) +
         fmt::format(
             "[[assemblies]]\ntype = \"poured\"\ncount = {}\nwidth = {}\ndepth = {}\norigin = [0.0, 0.0, "
             "0.0]\ndensity = 2.65\nradius = 1.0\nsettle_time = {}\n",
             long(o.nx) * o.ny * o.nz, kSpacing * o.nx, kSpacing * o.ny, o.pour_seconds);
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

namespace {
// LAMMPS's read_data text for atom_style sphere (id type diameter density x y z), the box the planes'.
std::string lammps_data(const Bed3dOptions& o, const std::vector<Body3Spec>& bodies, double top) {
  std::string t = fmt::format(
      "LAMMPS data file: grainlab bench bed3d poured {} x {} x {}\n\n{} atoms\n1 atom types\n\n0 {} xlo "
      "xhi\n0 "
      "{} ylo yhi\n0 {} zlo zhi\n\nAtoms # sphere\n\n",
      o.nx, o.ny, o.nz, bodies.size(), kSpacing * o.nx, kSpacing * o.ny, top + 10);
  long id = 0;
  for (const Body3Spec& b : bodies)
    t += fmt::format("{} 1 {} 2.65 {} {} {}\n", ++id, 2 * b.radius, b.position.x(), b.position.y(),
                     b.position.z());
  return t;
}

// The poured assembly's grains where the pour leaves them: expanded_bodies3d's bodies, bit for bit (the
// same settling run, advanced in slices so that a long pour can say how far it is).
std::vector<Body3Spec> poured_bodies(const Scene& pour, const Bed3dOptions& o) {
  const Scene settle = dem::pour_settling_scene(pour);
  dem::World3d world(settle);
  const double end = pour.assemblies[0].settle_time;
  constexpr int kSlices = 200;
  for (int k = 1; k <= kSlices; ++k) {
    world.advance_to(k == kSlices ? end : end * k / kSlices);
    if (o.progress) o.progress(world.time(), end);
  }
  std::vector<Body3Spec> out = settle.bodies3d;
  for (std::size_t i = 0; i < out.size(); ++i) {  // (the world keeps the scene's order)
    out[i].position = world.bodies()[i].x;
    out[i].orientation = world.bodies()[i].q;
    out[i].velocity = pour.assemblies[0].velocity3;
  }
  return out;
}

// Pours the bed, and writes it as BASE.toml and BASE.data (each atomically, by rank 0 under mpirun), its
// spheres stopped where the pour leaves them.
int pour_bed3d(const Bed3dOptions& o) {
  const Scene pour = parse_scene(poured_bed3d_scene_toml(o), "<bench bed3d poured>");
  fmt::print(stderr, "bench bed3d: pouring {} spheres into {} x {} cm and settling them for {} s...\n",
             long(o.nx) * o.ny * o.nz, kSpacing * o.nx, kSpacing * o.ny, o.pour_seconds);
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<Body3Spec> bodies = poured_bodies(pour, o);
  if (parallel::rank() != 0) return 0;
  std::string toml = bed3d_head(fmt::format("bench bed3d poured {} x {} x {}, as poured", o.nx, o.ny, o.nz));
  double mean_z = 0, top = 0;
  for (const Body3Spec& b : bodies) {
    toml += sphere_toml(b.position);
    mean_z += b.position.z() / double(bodies.size());
    top = std::max(top, b.position.z() + b.radius);
  }
  write_file_atomically(o.pour_to + ".toml", toml + bed3d_planes(o));
  write_file_atomically(o.pour_to + ".data", lammps_data(o, bodies, top));
  fmt::print(
      "bed3d poured {} x {} x {} = {} spheres in {:.0f} s: mean height {:.6f} cm, top {:.4f} cm; {}.toml "
      "(grainlab bench bed3d --bed-scene), {}.data (LAMMPS: bench/bed3d_data.in)\n",
      o.nx, o.ny, o.nz, bodies.size(),
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), mean_z, top, o.pour_to,
      o.pour_to);
  return 0;
}

Scene bench_scene(const Bed3dOptions& o) {
  if (o.bed_scene.empty()) return parse_scene(bed3d_scene_toml(o), "<bench bed3d>");
  Scene s = load_scene(o.bed_scene);
  if (s.dimension != 3)
    throw InputError({o.bed_scene, 0}, "--bed-scene", "bench bed3d times 3-D scenes only");
  return s;
}
}  // namespace

int run_bed3d_bench(const Bed3dOptions& o) {
  if (o.scene_only) {
    fmt::print("{}", o.pour_to.empty() ? bed3d_scene_toml(o) : poured_bed3d_scene_toml(o));
    return 0;
  }
  if (!o.pour_to.empty()) return pour_bed3d(o);
  const Scene scene = bench_scene(o);
  const std::string what = o.bed_scene.empty() ? fmt::format("{} x {} x {}", o.nx, o.ny, o.nz) : o.bed_scene;
  // Under mpirun the bed is spread over the ranks (slabs along x); the time is the slowest rank's.
  const int ranks = parallel::size();
  const double dt = scene.accuracy.dt, before = heap_in_use();
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
      "bed3d {} = {} spheres{}, {} settling + {} timed Verlet steps, median of {}: {:.3f} s, "
      "{:.4g} "
      "particle-steps/s, {:.0f} bytes per particle; mean height {:.6f} cm, kinetic energy {:.6g} erg\n",
      what, n, ranks > 1 ? fmt::format(" on {} ranks", ranks) : "", o.settle_steps, o.timed_steps, o.repeats,
      median, rate, bytes / double(n), mean_z, ke);
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
