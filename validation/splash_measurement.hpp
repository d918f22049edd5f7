#pragma once
// The splash function measured: impacts over a grid of incident speed and angle on loose beds, written
// as a grainlab-splash/1 file (saltation/splash_file.hpp, docs/splash-file.md) for the saltation and
// ripple models.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "splash_file.hpp"

namespace grainlab::validation {

struct SplashOptions {
  std::string engine = "native";
  std::size_t runs = 100;  // impacts per cell
  std::size_t beds = 3;    // independent loose beds (impact i uses bed i mod beds)
  std::uint64_t seed = 1;
  int dimension = 2;   // 3: impacts with spheres on poured beds (impacts3d.hpp), lateral columns kept
  int spheres = 2000;  // 3-D: spheres per bed
  // 3-D: the box's x and y in cm; {0, 0}: the 67.3 x 20 cm box, its area scaled to `spheres`.
  double box_width = 0, box_depth = 0;
  // 3-D, native engine: only the bed grains within this many bed-grain diameters of the impact point
  // move, the rest are held (ImpactOptions::active_radius); 0: the whole bed.
  double active_zone = 0;
  // 3-D: keep each poured bed in `{bed_checkpoint}.bed-K.h5` (K = 1..beds; the sand gun's checkpoint form)
  // and read it from there when it holds a bed of the same spec: a wide bed is poured once for every run,
  // zone and restart. Empty: pour every time.
  std::string bed_checkpoint;
  std::vector<double> speeds_cm_s = {300, 1000, 2000, 4000, 8100};
  std::vector<double> angles_deg = {5, 15, 25, 45, 70};
  std::function<void(const std::string&)> log;
  std::function<void(std::size_t, std::size_t)> progress;
  // Checkpoints: called with the file so far (complete = "false") after every cell; a run resumed from
  // one (`resume`) computes only the missing cells and ends with the same file as an uninterrupted run.
  std::function<void(const saltation::SplashFile&)> checkpoint;
  const saltation::SplashFile* resume = nullptr;
  std::size_t stop_after_cells = 0;  // stop (unfinished) once this many cells are done (0: never)
};
// The quick grid for CI: the same cells, 2 impacts each on one bed.
SplashOptions quick_splash_options();

// One cell's per-impact samples, and the moments of docs/splash-file.md from them.
struct CellSamples {
  std::size_t impacts = 0, rebounds = 0;
  std::vector<double> eps_ix, eps_iy, eps_i, theta_i, ejecta_per_impact, ejecta_vx, ejecta_vy, ejecta_speed,
      ejecta_angle, reptation_per_ejectum;
};
void set_cell_moments(saltation::SplashCell& c, const CellSamples& s);

// Runs every cell (ensembles spread over the MPI ranks) and returns the file's contents. Throws
// InputError if `resume` was made with other options.
saltation::SplashFile measure_splash(const SplashOptions& o);

}  // namespace grainlab::validation
