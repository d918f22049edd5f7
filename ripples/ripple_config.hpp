#pragma once
// Ripple models read TOML configs with the scenes' strict reader: unknown keys, wrong types and values out
// of range stop with the file, line and key, and exit status 2. docs/ripples.md lists the keys.
#include <toml++/toml.h>

#include <map>
#include <string>
#include <vector>

#include "bin_model.hpp"
#include "lattice_model.hpp"
#include "triangles.hpp"

namespace grainlab::ripples {

struct BinModelRun {
  BinModelParams params;
  long shots = 2000000;
  int frames = 100;  // surfaces recorded for h(x, t)
  std::string text;  // the config as read
};

// Reads `[bins]` from TOML text (`path` names it in errors). Throws InputError.
BinModelRun parse_bin_model_config(const std::string& text, const std::string& path);
BinModelRun read_bin_model_config(const std::string& path);

struct LatticeRun {
  LatticeParams params;
  // Splash mode: a grainlab-splash/1 file (or "sand-gun" for Tables 3.11-3.12) whose ejecta hop lengths
  // replace the fixed hops, taken from its cells nearest splash_angle (deg) and splash_speed (sqrt(g d);
  // 0: every speed pooled). The caller turns them into params.hops_d (ripples/ does not read HDF5).
  std::string splash;
  double splash_angle = 15, splash_speed = 0;
  // Wind mode (the thesis's general model in 2-D), when > 0: the splash file drives the Ch. IV steady
  // wind at this u* (cm/s); the shots come in at its mean impact angle and each recorded ejectum of the
  // cell nearest its mean impact hops as far as it flies through that wind (splash_angle, splash_speed
  // and impact_angle are then not used).
  double splash_wind = 0;
  double ejections_per_grain = 10;  // run length: impacts per surface grain
  int frames = 100;
  std::string text;
};

// What splash mode takes from a splash file: the hops (grain diameters, negative upstream) and, in wind
// mode, the steady wind's mean impact angle for the shots (deg; negative: keep impact_angle).
struct SplashHops {
  std::vector<double> hops_d;
  double impact_deg = -1;
  std::map<std::string, double> wind_state;  // wind mode: what the steady wind made of the splash
};
void apply_splash_hops(LatticeRun& run, const SplashHops& hops);
// Reads `[lattice]` (docs/ripples.md lists the keys). Throws InputError.
LatticeRun parse_lattice_config(const std::string& text, const std::string& path);
LatticeRun read_lattice_config(const std::string& path);

// Haff's worms on a ring ([worms]) and one triangular collision ([triangles]); docs/ripples.md lists the
// keys. Throw InputError.
struct WormRingRun {
  int worms = 200, length = 2, steps = 200000, records = 50;
  double A = 0.6;
  std::uint64_t seed = 1;
  std::string text;
};
WormRingRun parse_worm_ring_config(const std::string& text, const std::string& path);
struct TriangleRun {
  TriangleParams params;
  double ratio = 0.6;  // upstream height / downstream height
  std::string text;
};
TriangleRun parse_triangle_config(const std::string& text, const std::string& path);
// A config parsed strictly (TOML syntax errors become InputError with the line), and the model's table in
// a config that must hold that table and nothing else.
toml::table config_root(const std::string& text, const std::string& path);
const toml::table& model_table(const toml::table& root, const std::string& name, const std::string& path);
// Command-line overrides `KEY=VALUE` (VALUE in TOML: 36, true, "lammel2017", [1.5, 0.5]) put into table
// `name` of root, replacing or adding keys, so a parameter sweep needs no edited copies of a config. Each
// keeps its own source, "--set KEY=VALUE", so a mistake in it is named as that option, not as a line of
// the file. InputError if one is not KEY=VALUE with a bare key and a TOML value.
void apply_overrides(toml::table& root, const std::string& name, const std::vector<std::string>& overrides);
// The text a run records as its config (output metadata, checkpoint fingerprints): the file's text, then
// one comment line per override, so that what was run can be read back and a checkpoint continues only
// under the same overrides.
std::string text_with_overrides(const std::string& text, const std::vector<std::string>& overrides);
// A config file's text (InputError if it cannot be read).
std::string read_config_text(const std::string& path);

}  // namespace grainlab::ripples
