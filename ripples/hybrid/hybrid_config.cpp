#include "hybrid_config.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "lammel_splash.hpp"
#include "ripple_config.hpp"
#include "ripple_run.hpp"
#include "toml_reader.hpp"

namespace grainlab::ripples::hybrid {

namespace {

void read_grains_and_wind(const TomlReader& r, RippleOptions& o) {
  o.diameter = r.number_or("diameter", o.diameter, Range{1e-5, 10, false});
  o.grain_density = r.number_or("grain_density", o.grain_density, Range::positive());
  o.fluid_density = r.number_or("fluid_density", o.fluid_density, Range::positive());
  o.viscosity = r.number_or("viscosity", o.viscosity, Range::positive());
  o.g = r.number_or("gravity", o.g, Range::positive());
  o.u_star = r.number_or("u_star", o.u_star, Range{0, 1e4, true});
  o.height = r.number_or("height", o.height, Range{2, 1e6, false});
  o.wind_interval = r.number_or("wind_interval", o.wind_interval, Range::positive());
  o.wind_memory = r.number_or("wind_memory", o.wind_memory, Range::positive());
}

void read_bed(const TomlReader& r, RippleOptions& o) {
  o.length = r.number_or("length", o.length, Range{3, 1e7, false});
  o.width = r.number_or("width", o.width, Range{3, 1e7, false});
  o.cell = r.number_or("cell", o.cell, Range{0.25, 1e4, false});
  o.packing = r.number_or("packing", o.packing, Range{0, 1, true});
  o.repose_deg = r.number_or("repose_angle", o.repose_deg, Range{1, 89, false});
  o.erodible = r.number_or("erodible", o.erodible, Range::non_negative());
  const std::string deposition = r.string_or("deposition", "nearest");
  if (deposition != "nearest" && deposition != "bilinear")
    r.fail("deposition",
           "must be \"nearest\" (the key point nearest the grain) or \"bilinear\" (shared among four)");
  o.bilinear = deposition == "bilinear";
  o.initial_amplitude = r.number_or("initial_amplitude", o.initial_amplitude, Range::non_negative());
  o.initial_wavelength = r.number_or("initial_wavelength", o.initial_wavelength, Range::non_negative());
  if (o.initial_amplitude > 0 && o.initial_amplitude >= o.erodible)
    r.fail("initial_amplitude", "must be smaller than the erodible depth");
  if (o.initial_amplitude > 0 && !(o.initial_wavelength >= 2 * o.cell && o.initial_wavelength <= o.length))
    r.fail("initial_wavelength",
           "must be between two cells and the bed's length when initial_amplitude is set");
}

// A bed of several sizes: `sizes` (2 to 8, in diameters of `diameter`), `fractions` by volume (equal when
// absent), and the surface layer's least depth.
void read_sizes(const TomlReader& r, RippleOptions& o) {
  o.affectable_depth = r.number_or("affectable_depth", o.affectable_depth, Range{0, 1e4, true});
  o.ejecta_size = r.string_or("ejecta_size", o.ejecta_size);
  if (o.ejecta_size != "struck" && o.ejecta_size != "local")
    r.fail("ejecta_size",
           "must be \"struck\" (the struck bed grain's size) or \"local\" (each ejectum's own)");
  if (!r.has("sizes")) {
    if (r.has("fractions")) r.fail("fractions", "needs sizes, one fraction per size");
    return;
  }
  const toml::array* a = r.node("sizes")->as_array();
  if (!a || a->size() < 2 || a->size() > 8)
    r.fail("sizes", "must be an array of 2 to 8 grain sizes, in diameters of `diameter`");
  o.sizes = r.numbers("sizes", a->size());
  for (double v : o.sizes)
    if (!(v >= 0.1 && v <= 10)) r.fail("sizes", "every size must be between 0.1 and 10 diameters");
  o.fractions.assign(o.sizes.size(), 1.0 / static_cast<double>(o.sizes.size()));
  if (r.has("fractions")) o.fractions = r.numbers("fractions", o.sizes.size());
  double sum = 0;
  for (double f : o.fractions) {
    if (!(f > 0)) r.fail("fractions", "every fraction must be positive");
    sum += f;
  }
  if (std::abs(sum - 1) > kFractionTolerance)
    r.fail("fractions", "must sum to 1 (they are the bed's volume fractions)");
}

void read_splash_and_run(const TomlReader& r, RippleOptions& o) {
  o.splash = r.string_or("splash", o.splash);
  // A Lammel parameter set, or a grainlab-splash/1 file of recorded impacts (the command reads it).
  if (!LammelParameters::is_named(o.splash) && !std::filesystem::is_regular_file(o.splash)) {
    // A relative path is read from the working directory (the presets' from the repository's top): say
    // where it was looked for, since a preset run from elsewhere fails here.
    std::error_code ec;
    const std::string where = std::filesystem::path(o.splash).is_relative()
                                  ? " (relative paths are read from the working directory, " +
                                        std::filesystem::current_path(ec).string() +
                                        "; the presets' from the repository's top)"
                                  : "";
    r.fail("splash", "must be a Lammel set (" + LammelParameters::names_quoted() +
                         ") or a grainlab-splash/1 file that exists; no file " + o.splash + where);
  }
  o.wind_loosened = r.boolean_or("wind_loosened", o.wind_loosened);
  const std::string launch = r.string_or("ejecta_launch", "normal");
  if (launch != "normal" && launch != "vertical")
    r.fail("ejecta_launch", "must be \"normal\" (to the local bed) or \"vertical\"");
  o.ejecta_vertical = launch == "vertical";
  const std::string frame = r.string_or("splash_frame", "facet");
  if (frame != "facet" && frame != "level")
    r.fail("splash_frame", "must be \"facet\" (the bed triangle hit) or \"level\"");
  o.splash_level = frame == "level";
  o.wind_follows_bed = r.boolean_or("wind_follows_bed", o.wind_follows_bed);
  o.wind_relief_fades = r.boolean_or("wind_relief_fades", o.wind_relief_fades);
  o.dead_rise = r.number_or("dead_rise", o.dead_rise, Range{0, 10, false});
  o.loosened_floor = r.number_or("loosened_floor", o.loosened_floor, Range{0, 1, true});
  o.collisions = r.boolean_or("collisions", o.collisions);
  o.collide_within_splash = r.boolean_or("collide_within_splash", o.collide_within_splash);
  o.collision_restitution = r.number_or("collision_restitution", o.collision_restitution, Range{0, 1, false});
  o.collision_friction = r.number_or("collision_friction", o.collision_friction, Range::non_negative());
  o.triggers = static_cast<int>(r.integer_or("triggers", o.triggers, 1, 10000000));
  o.dt_max = r.number_or("dt_max", o.dt_max, Range{0, 1, true});
  o.swept = r.boolean_or("swept", o.swept);
  o.fast_substeps = r.boolean_or("fast_substeps", o.fast_substeps);
  if (o.fast_substeps && !o.swept)
    r.fail("fast_substeps", "needs swept = true: fast grains are found along their paths");
  o.travel = r.number_or("travel", o.travel, Range{0, 4, true});
  if (!o.swept && o.travel > 0.5)
    r.fail("travel", "above 0.5 d grains can pass through each other unseen: set swept = true with it");
  o.duration = r.number_or("duration", o.duration, Range{0, 1e9, true});
  o.frame_every = r.number_or("frame_every", o.frame_every, Range{0, 1e9, true});
  o.sample_every = r.number_or("sample_every", o.sample_every, Range{0, 1e9, true});
  o.seed = static_cast<std::uint64_t>(r.integer_or("seed", static_cast<std::int64_t>(o.seed), 0, INT64_MAX));
}

}  // namespace

namespace {

// Every number as a double: `u_star = 40` and `u_star = 40.0` are read alike (and an integer key given as
// 40.0 is refused before this matters).
void numbers_as_doubles(toml::table& t);
void numbers_as_doubles(toml::array& a) {
  for (auto it = a.begin(); it != a.end(); ++it)
    if (it->is_integer())
      it = a.replace(it, static_cast<double>(it->as_integer()->get()));
    else if (toml::table* sub = it->as_table())
      numbers_as_doubles(*sub);
    else if (toml::array* inner = it->as_array())
      numbers_as_doubles(*inner);
}
void numbers_as_doubles(toml::table& t) {
  std::vector<std::string> integers;
  for (auto&& [key, value] : t)
    if (value.is_integer())
      integers.emplace_back(key.str());
    else if (toml::table* sub = value.as_table())
      numbers_as_doubles(*sub);
    else if (toml::array* a = value.as_array())
      numbers_as_doubles(*a);
  for (const std::string& key : integers)
    t.insert_or_assign(key, static_cast<double>(t[key].as_integer()->get()));
}

// The values a run reads, in one printed form: no comments or layout, no duration, numbers as doubles.
std::string printed_values(const toml::table& root) {
  toml::table values = root;
  if (toml::table* h = values["hybrid"].as_table()) h->erase("duration");
  numbers_as_doubles(values);
  std::ostringstream printed;
  printed << values;
  return printed.str();
}

}  // namespace

HybridConfig parse_hybrid_config(const std::string& text, const std::string& path,
                                 const std::vector<std::string>& overrides) {
  toml::table root = config_root(text, path);
  apply_overrides(root, "hybrid", overrides);
  TomlReader r(model_table(root, "hybrid", path), "hybrid", path, "docs/hybrid.md");
  HybridConfig c;
  RippleOptions& o = c.options;
  read_grains_and_wind(r, o);
  read_bed(r, o);
  read_splash_and_run(r, o);
  read_sizes(r, o);
  r.finish();
  if (!o.sizes.empty() && !LammelParameters::is_named(o.splash))
    r.fail("sizes", "a recorded splash holds impacts of one grain size: use a Lammel set (" +
                        LammelParameters::names_quoted() + ")");
  // Defaults follow a short duration; values given must fit it.
  if (!r.has("frame_every")) o.frame_every = std::min(o.frame_every, o.duration);
  if (!r.has("sample_every")) o.sample_every = std::min(o.sample_every, o.frame_every);
  if (o.cell > o.length / 3 || o.cell > o.width / 3)
    r.fail("cell", "the bed needs at least 3 cells each way");
  if (const std::string why = cell_too_small(o); !why.empty()) r.fail(r.has("cell") ? "cell" : "sizes", why);
  if (o.frame_every > o.duration) r.fail("frame_every", "must not be longer than the duration");
  if (o.sample_every > o.frame_every) r.fail("sample_every", "must not be longer than frame_every");
  c.text = text_with_overrides(text, overrides);
  c.values = printed_values(root);
  return c;
}

std::string config_differences(const std::string& other, const HybridConfig& c) {
  toml::table theirs, ours;
  try {
    theirs = toml::parse(other), ours = toml::parse(c.values);
  } catch (const toml::parse_error&) {
    return {};
  }
  theirs = toml::parse(printed_values(theirs));  // the same form as ours
  std::vector<std::string> keys;
  for (const toml::table* t : {&theirs, &ours})
    if (const toml::table* h = (*t)["hybrid"].as_table())
      for (auto&& [key, value] : *h) keys.emplace_back(key.str());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  auto shown = [](const toml::table& t, const std::string& key) {
    const toml::node* n = t["hybrid"][key].node();
    if (!n) return std::string("not given");
    std::ostringstream s;
    n->visit([&s](const auto& v) { s << v; });
    return s.str();
  };
  std::string out;
  for (const std::string& key : keys) {
    const std::string a = shown(theirs, key), b = shown(ours, key);
    if (a != b) out += (out.empty() ? "" : "; ") + key + ": " + a + " there, " + b + " here";
  }
  return out;
}

}  // namespace grainlab::ripples::hybrid
