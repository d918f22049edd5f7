#pragma once
// The grain beds of the thesis's impact simulations (Ch. III): 384 discs of r_b = 1 cm in an open-topped
// 67.3 x 24.1 cm box, k_n = k_s = 6e9 dyn/cm, pair restitution 0.85, built as "loose" or "dense" by a
// documented recipe (docs/impacts.md), plus a periodic-in-x variant. A bed is kept as a grainlab run file
// whose scene text lists every disc at rest, so any engine can load the very same bed.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene.hpp"

namespace grainlab::validation {

struct BedSpec {
  std::string preparation = "loose";  // "loose" (poured with friction) or "dense" (poured frictionless)
  std::uint64_t seed = 1;
  int count = 384;
  double width = 67.3, height = 24.1;  // the box (a periodic bed: period and nominal height)
  bool periodic = false;
  bool levelled = true;  // poured with 15 % extra discs, the highest scraped off (a flat surface)
  double radius = 1.0, density = 2.0, k_n = 6e9, restitution = 0.85, mu = 0.5;
};

// The exposed grains of a bed, left to right, and its steps.
struct BedSurface {
  std::vector<std::size_t> grains;  // indices into the bodies, exposed from above, by x
  std::vector<std::uint8_t> type;   // per body: 0 buried, 1 surface, 2 brink, 3 anti-brink
  double top = 0;                   // "top of the bed": highest surface point in the middle 80 %
  double roughness = 0;             // standard deviation of the exposed grains' tops (middle 80 %)
  int brinks = 0, anti_brinks = 0;  // steps down / up (downstream = +x) of at least one radius
};
// Brinks: two consecutive exposed grains whose centres drop by at least r_b going downstream; the two
// grains just upstream of the drop are brink grains (the thesis's definition). Anti-brinks mirror it:
// the two grains on top of a rise of at least r_b.
BedSurface bed_surface(const std::vector<BodySpec>& bodies, double xmin, double xmax);

struct BedStats {
  double packing_fraction = 0;    // disc area / area, in the bed's interior (2 diameters from walls and top)
  double coordination = 0;        // mean contacts per disc (all discs, walls counted)
  double top = 0, roughness = 0;  // cm
  int brinks = 0, anti_brinks = 0;
  double kinetic_energy = 0;  // erg, when built (before velocities are zeroed)
  double build_seconds = 0;
};

struct Bed {
  BedSpec spec;
  Scene scene;  // every disc listed as a body, at rest; walls; the thesis's material
  BedStats stats;
  BedSurface surface;
  std::string source;  // the file it came from, or "built"
};

// Pours and settles a bed (a few seconds of computing); `log` hears the stages.
Bed build_bed(const BedSpec& spec, const std::function<void(const std::string&)>& log = {});
// Throws InputError (under `key`) unless `preparation` is "loose" or "dense": the two of either dimension.
void check_preparation(const std::string& preparation, const std::string& key);
// The TOML scene text of a bed whose discs sit at `bodies`.
std::string bed_scene_text(const BedSpec& spec, const std::vector<BodySpec>& bodies, double duration);
BedStats measure_bed(const Scene& scene, const BedSpec& spec);
// Duration of an undamped linear contact of stiffness k between masses m1 and m2: pi sqrt(m_eff / k).
// Verlet steps are fractions of the shortest one.
inline double contact_time(double k, double m1, double m2) {
  return M_PI * std::sqrt(m1 * m2 / (m1 + m2) / k);
}
// Writes the bed as a grainlab run file (one short native run from rest, so ParaView shows it).
void write_bed(const Bed& bed, const std::string& path, bool overwrite);
// Reads a bed file; throws InputError naming the file and what is wrong.
Bed read_bed(const std::string& path);

}  // namespace grainlab::validation
