#include "ripple_config.hpp"

#include <fstream>
#include <sstream>

#include "input_error.hpp"
#include "toml_reader.hpp"

namespace grainlab::ripples {

BinModelRun parse_bin_model_config(const std::string& text, const std::string& path) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw InputError({path, static_cast<int>(e.source().begin.line)}, "", std::string(e.description()));
  }
  TomlReader top(root, "", path);
  const toml::table* t = top.subtable("bins");
  if (!t) throw InputError({path, 0}, "bins", "the config needs a [bins] table (docs/ripples.md)");
  top.finish();
  TomlReader r(*t, "bins", path);
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
  std::ifstream in(path);
  if (!in) throw InputError({path, 0}, "", "cannot be read");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_bin_model_config(ss.str(), path);
}

}  // namespace grainlab::ripples
