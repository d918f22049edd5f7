#include "ripple_config.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "input_error.hpp"
#include "toml_reader.hpp"

namespace grainlab::ripples {

toml::table config_root(const std::string& text, const std::string& path) {
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError({path, static_cast<int>(e.source().begin.line)}, "", std::string(e.description()));
  }
}

void apply_overrides(toml::table& root, const std::string& name, const std::vector<std::string>& overrides) {
  toml::table* t = root[name].as_table();
  if (!t) return;  // model_table names the missing table
  for (const std::string& o : overrides) {
    const std::string where = "--set " + o;
    const auto eq = o.find('=');
    const std::string key = eq == std::string::npos ? "" : o.substr(0, eq);
    const bool bare = !key.empty() && std::all_of(key.begin(), key.end(), [](unsigned char c) {
      return std::isalnum(c) || c == '_' || c == '-';
    });
    if (!bare)
      throw InputError({where, 0}, "",
                       "must be KEY=VALUE: a key of the [" + name + "] table, '=', and a TOML value");
    // A bare word that is not TOML (lammel2017, a file name) is taken as a string, as a shell user means it.
    std::string value = o.substr(eq + 1);
    const bool word = !value.empty() && std::all_of(value.begin(), value.end(), [](unsigned char c) {
      return std::isalnum(c) || std::strchr("_-./", c);
    });
    toml::table one;
    try {
      try {
        one = toml::parse(key + " = " + value, where);
      } catch (const toml::parse_error&) {
        if (!word) throw;
        one = toml::parse(key + " = \"" + value + "\"", where);
      }
    } catch (const toml::parse_error& e) {
      throw InputError({where, 0}, name + "." + key,
                       "the value is not one TOML value (a number, true or false, a \"string\" in quotes, "
                       "an [array]): " +
                           std::string(e.description()));
    }
    if (one.size() != 1) throw InputError({where, 0}, name + "." + key, "give one value, without a newline");
    t->insert_or_assign(key, std::move(*one.get(key)));
  }
}

std::string text_with_overrides(const std::string& text, const std::vector<std::string>& overrides) {
  if (overrides.empty()) return text;
  std::string s = text;
  if (!s.empty() && s.back() != '\n') s += '\n';
  for (const std::string& o : overrides) s += "# --set " + o + "\n";
  return s;
}

namespace {

std::string read_text(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw InputError({path, 0}, "", "is a folder, not a config file");
  std::ifstream in(path);
  if (!in) throw InputError({path, 0}, "", "cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

const toml::table& model_table(const toml::table& root, const std::string& name, const std::string& path) {
  const std::string docs = name == "hybrid" ? "docs/hybrid.md" : "docs/ripples.md";
  TomlReader top(root, "", path, docs);
  const toml::table* t = top.subtable(name);
  if (!t) throw InputError({path, 0}, name, "the config needs a [" + name + "] table (" + docs + ")");
  top.finish();
  return *t;
}

BinModelRun parse_bin_model_config(const std::string& text, const std::string& path) {
  const toml::table root = config_root(text, path);
  TomlReader r(model_table(root, "bins", path), "bins", path, "docs/ripples.md");
  BinModelRun run;
  BinModelParams& p = run.params;
  p.bins = static_cast<int>(r.integer_or("bins", p.bins, 16, 10000000));
  p.bin_width = r.number_or("bin_width", p.bin_width, Range::positive());
  p.depth = r.number_or("depth", p.depth, Range::positive());
  p.roughness = r.number_or("roughness", p.roughness, Range::non_negative());
  p.impact_deg = r.number_or("impact_angle", p.impact_deg, Range{0, 89, true});
  p.hop_bins = static_cast<int>(r.integer_or("hop_bins", p.hop_bins, 1, 1000000));
  p.repose_deg = r.number_or("repose_angle", p.repose_deg, Range{0, 89, true});
  p.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, 0, INT64_MAX));
  run.shots = r.integer_or("shots", run.shots, 0, INT64_MAX);
  run.frames = static_cast<int>(r.integer_or("frames", run.frames, 1, 100000));
  r.finish();
  if (p.hop_bins >= p.bins) r.fail("hop_bins", "must be smaller than bins");
  run.text = text;
  return run;
}

BinModelRun read_bin_model_config(const std::string& path) {
  return parse_bin_model_config(read_text(path), path);
}

LatticeRun parse_lattice_config(const std::string& text, const std::string& path) {
  const toml::table root = config_root(text, path);
  TomlReader r(model_table(root, "lattice", path), "lattice", path, "docs/ripples.md");
  LatticeRun run;
  LatticeParams& p = run.params;
  p.columns = static_cast<int>(r.integer_or("columns", p.columns, 16, 100000000));
  p.impact_deg = r.number_or("impact_angle", p.impact_deg, Range{0, 89, true});
  p.forward = static_cast<int>(r.integer_or("forward", p.forward, 0, 10000000));
  p.backward = static_cast<int>(r.integer_or("backward", p.backward, 0, 10000000));
  p.brink_probability = r.number_or("brink_probability", p.brink_probability, Range{0, 1, false});
  p.brink_lookahead = static_cast<int>(r.integer_or("brink_lookahead", p.brink_lookahead, 0, 10000000));
  p.hits_per_point = static_cast<int>(r.integer_or("hits_per_point", p.hits_per_point, 1, 1000));
  p.depth = static_cast<int>(r.integer_or("depth", p.depth, 2, 1000000));
  p.roughness = r.number_or("roughness", p.roughness, Range{0, 1, false});
  p.land_downhill = r.boolean_or("land_downhill", p.land_downhill);
  p.initial_amplitude = r.number_or("initial_amplitude", p.initial_amplitude, Range::non_negative());
  p.initial_wavelength = r.number_or("initial_wavelength", p.initial_wavelength, Range::non_negative());
  p.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, 0, INT64_MAX));
  run.ejections_per_grain = r.number_or("ejections_per_grain", run.ejections_per_grain, Range::positive());
  run.splash = r.string_or("splash", "");
  run.splash_angle = r.number_or("splash_angle", run.splash_angle, Range{0, 90, true});
  run.splash_speed = r.number_or("splash_speed", run.splash_speed, Range::non_negative());
  run.splash_wind = r.number_or("splash_wind", run.splash_wind, Range{0, 1000, false});
  run.frames = static_cast<int>(r.integer_or("frames", run.frames, 1, 100000));
  r.finish();
  if (p.columns % 2) r.fail("columns", "must be even (a lattice spacing is two columns)");
  if (2L * std::max(p.forward, p.backward) >= p.columns)
    r.fail("forward", "hops must be shorter than the domain");
  if (2L * p.brink_lookahead + 4 >= p.columns)
    r.fail("brink_lookahead", "must be shorter than half the domain");
  if (run.splash_wind > 0 && (run.splash.empty() || run.splash == "sand-gun"))
    r.fail("splash_wind", "needs a splash file of recorded impacts (splash = \"FILE.h5\")");
  if (p.initial_amplitude > 0 && p.roughness > 0)
    r.fail("initial_amplitude", "a seeded sine needs the flat start (roughness = 0)");
  if (p.initial_amplitude > 0 && p.initial_wavelength <= 0)
    r.fail("initial_wavelength", "a seeded sine needs its wavelength (lattice spacings)");
  if (2 * p.initial_amplitude * std::sin(M_PI * lattice_seeded_waves(p) / p.columns) >= 1)
    r.fail("initial_amplitude", "the seeded sine would be steeper than the lattice's 30 deg slope");
  run.text = text;
  return run;
}

LatticeRun read_lattice_config(const std::string& path) {
  return parse_lattice_config(read_text(path), path);
}

WormRingRun parse_worm_ring_config(const std::string& text, const std::string& path) {
  const toml::table root = config_root(text, path);
  TomlReader r(model_table(root, "worms", path), "worms", path, "docs/ripples.md");
  WormRingRun run;
  run.worms = static_cast<int>(r.integer_or("worms", run.worms, 2, 10000000));
  run.length = static_cast<int>(r.integer_or("length", run.length, 1, 1000000));
  run.A = r.number_or("A", run.A, Range{0, 1, true});
  run.steps = static_cast<int>(r.integer_or("steps", run.steps, 0, 2000000000));
  run.records = static_cast<int>(r.integer_or("records", run.records, 1, 100000));
  run.seed = static_cast<std::uint64_t>(r.integer_or("seed", 1, 0, INT64_MAX));
  r.finish();
  run.text = text;
  return run;
}

TriangleRun parse_triangle_config(const std::string& text, const std::string& path) {
  const toml::table root = config_root(text, path);
  TomlReader r(model_table(root, "triangles", path), "triangles", path, "docs/ripples.md");
  TriangleRun run;
  run.ratio = r.number_or("ratio", run.ratio, Range{0, 1, true});
  run.params.beta_deg = r.number_or("stoss_angle", run.params.beta_deg, Range{0, 45, true});
  run.params.alpha_deg = r.number_or("lee_angle", run.params.alpha_deg, Range{0, 45, true});
  run.params.law = r.string_or("law", run.params.law);
  r.finish();
  if (run.params.law != "target" && run.params.law != "brink")
    r.fail("law", "must be \"target\" or \"brink\"");
  if (!(run.ratio < 1)) r.fail("ratio", "must lie below 1 (the upstream ripple is the smaller)");
  run.text = text;
  return run;
}

std::string read_config_text(const std::string& path) {
  return read_text(path);
}

void apply_splash_hops(LatticeRun& run, const SplashHops& hops) {
  run.params.hops_d = hops.hops_d;
  if (hops.impact_deg >= 0) run.params.impact_deg = hops.impact_deg;
}

}  // namespace grainlab::ripples
