// Run under mpirun by ctest (2 and 3 ranks): a 3-D bed built with its spheres spread over the ranks is,
// on every rank, the bed each rank builds alone, bit for bit; and a spread build checkpointed part-way
// through a stage (rank 0 writes the file, every rank reads it) continues to that same bed.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "impacts3d.hpp"
#include "mpi_test_start.hpp"
#include "parallel.hpp"
#include "sand_gun3d.hpp"

using namespace grainlab;
using namespace grainlab::validation;

namespace {

int differences(const Bed3d& a, const Bed3d& b, const char* what) {
  int bad = 0;
  const auto& x = a.scene.bodies3d;
  const auto& y = b.scene.bodies3d;
  if (x.size() != y.size() || a.removed != b.removed || a.probes != b.probes || a.top != b.top) {
    fmt::print(stderr, "rank {}: {}: {} spheres (removed {}, probes {}, top {}) against {} ({}, {}, {})\n",
               parallel::rank(), what, y.size(), b.removed, b.probes, b.top, x.size(), a.removed, a.probes,
               a.top);
    return 1;
  }
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i].position != y[i].position || x[i].orientation.coeffs() != y[i].orientation.coeffs()) ++bad;
  if (bad) fmt::print(stderr, "rank {}: {}: {} spheres elsewhere than alone\n", parallel::rank(), what, bad);
  return bad ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  int failures = testing::start_mpi_test(argc, argv);
  Bed3dSpec spec;  // the thesis's spheres, in a box long enough for 3 slabs of about 5 radii
  spec.count = 240;
  spec.width = 16, spec.depth = 8;
  const Bed3d alone = build_bed3d(spec, {}, {}, {}, 600, BedRanks::each_alone);
  std::vector<Bed3dBuild> within;  // rank 0's records handed over inside a stage (every 2,000 steps)
  const Bed3d spread = build_bed3d(
      spec, {}, {},
      [&](const Bed3dBuild& b) {
        if (parallel::rank() == 0 && !b.run_under_way.empty()) within.push_back(b);
      },
      0);
  failures += differences(alone, spread, "spread");

  // Continued from part-way through the probe's run if there is one (else the middle record): rank 0
  // writes the checkpoint, every rank reads it.
  const std::string path = fmt::format("mpi-bed-build-{}.ck.h5", parallel::size());
  double have = 0;
  if (parallel::rank() == 0 && !within.empty()) {
    auto pick = std::find_if(within.begin(), within.end(),
                             [](const Bed3dBuild& b) { return !b.runs_done.rows.empty(); });
    if (pick == within.end()) pick = within.begin() + static_cast<long>(within.size() / 2);
    SandGunProgress p;
    p.build = *pick;
    p.bed.spec = spec;
    write_sand_gun_checkpoint(path, p, 1);
    have = 1;
    fmt::print("continuing from stage {} ({} finished runs' rows, {} world tables)\n", pick->stage,
               pick->runs_done.rows.size(), pick->run_under_way.size());
  }
  if (parallel::max_all(have) == 0) {
    fmt::print(stderr, "no record inside a stage\n");
    ++failures;
  } else {
    const std::optional<SandGunProgress> back = read_sand_gun_checkpoint(path, spec, 1);
    if (!back) {
      fmt::print(stderr, "rank {}: the checkpoint was not read\n", parallel::rank());
      ++failures;
    } else {
      failures += differences(alone, build_bed3d(spec, {}, back->build), "continued");
    }
  }
  parallel::barrier();
  if (parallel::rank() == 0) std::filesystem::remove(path);
  failures = static_cast<int>(parallel::max_all(failures));
  if (parallel::rank() == 0)
    fmt::print("{} spheres on {} ranks: {}\n", alone.scene.bodies3d.size(), parallel::size(),
               failures ? "MISMATCH" : "the bed built alone, bit for bit");
  parallel::finalize();
  return failures ? 1 : 0;
}
