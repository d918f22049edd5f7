#pragma once
// The splash function as data: the `grainlab-splash/1` HDF5 file (schema in docs/splash-file.md). The
// impacts measurement writes it; the saltation and ripple models read it. This library knows nothing of
// the DEM engine: a splash reaches the models only through this file.
//
// Everything in the file is non-dimensional: velocities in sqrt(g d), lengths in d (d: the bed grain's
// diameter), with the scale stored so a model can put it back for any grain size.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace grainlab::saltation {

inline constexpr const char* kSplashSchema = "grainlab-splash/1";

// One statistic of a cell: mean, standard deviation and 95 % interval of the mean.
struct SplashMoment {
  double mean = 0, sd = 0, lo = 0, hi = 0;
};

// One impact's rebound: impact index, rebounded (1/0), velocity at departure, spin x d / sqrt(g d).
using ReboundRow = std::array<double, 5>;
// One ejectum: impact index, velocity one diameter above the top, launch velocity (carried back to the
// grain's original centre height), origin relative to the impact point, type (0 other, 1 target,
// 2 brink, 3 anti-brink).
using EjectumRow = std::array<double, 8>;

struct SplashCell {
  double speed = 0;      // incident speed / sqrt(g d)
  double angle_deg = 0;  // incident angle below the horizontal
  std::size_t impacts = 0;
  std::vector<ReboundRow> rebound;  // empty in a measured file with moments only
  std::vector<EjectumRow> ejecta;
  // 3-D files only (empty in 2-D), where x is downstream and y vertical as in 2-D and the third axis is
  // across the incident plane: each rebound row's velocity across it, and each ejectum's velocity across
  // it and where it sat across it (d).
  std::vector<double> rebound_lateral;
  std::vector<std::array<double, 2>> ejecta_lateral;
  std::map<std::string, SplashMoment> moments;
};

struct SplashFile {
  std::map<std::string, std::string> text;  // schema, kind ("simulated"/"measured"), source, engine, ...
  double grain_diameter_cm = 0, gravity_cm_s2 = 981, grain_density = 0;
  int dimension = 2;                       // 3: impacts on spheres, with the lateral columns of SplashCell
  std::vector<double> speeds, angles_deg;  // the grid; cells are row-major: [speed index][angle index]
  std::vector<SplashCell> cells;

  double velocity_scale() const;  // sqrt(g d), cm/s
  const SplashCell& cell(std::size_t speed_index, std::size_t angle_index) const;
  // The grid cell nearest to an impact (speed / sqrt(g d), angle in degrees), distance measured in grid
  // steps so neither axis dominates.
  const SplashCell& nearest(double speed, double angle_deg) const;
};

// The moment names a file carries per cell (a measured file may carry a subset).
const std::vector<std::string>& splash_moment_names();

// Writes atomically (temporary file, then rename); throws std::runtime_error if `path` exists and
// !overwrite, or on an HDF5 failure.
void write_splash_file(const std::string& path, const SplashFile& f, bool overwrite);
// Reads and checks a splash file; throws grainlab::InputError naming the file and what is wrong (not
// HDF5, wrong schema, missing or misshapen datasets, non-finite numbers, a grid that does not match
// its cells).
// A checkpoint of an unfinished measurement (attribute complete = "false", fewer cells than its grid) is
// refused unless `allow_partial`.
SplashFile read_splash_file(const std::string& path, bool allow_partial = false);

// Hop lengths of the ejecta (grain diameters, signed: negative is upstream) in the cells nearest an impact
// angle (deg) and speed (sqrt(g d); 0: every speed pooled). Simulated files give each ejectum's ballistic
// range 2 v_x v_y (velocities in sqrt(g d), so the range is in d); a file with moments only (the sand
// gun) gives an exponential of its mean reptation length per ejectum, all downstream, as 1,000 quantiles.
// Empty if the cells hold neither. The ripple models' splash mode reads its hops from here.
std::vector<double> ejecta_hop_lengths(const SplashFile& f, double angle_deg, double speed);

// Table 3.11 and 3.12's sand-gun experiment (Kelso Dunes sand, d = 0.078 cm) as a measured splash file:
// one cell per row of the tables, moments only.
SplashFile sand_gun_splash();

}  // namespace grainlab::saltation
