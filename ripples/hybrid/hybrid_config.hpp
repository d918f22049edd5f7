#pragma once
// `[hybrid]` configs for `grainlab ripples hybrid --config FILE`: every key of the 3-D hybrid model's
// ripple run, checked like scene keys (unknown keys, wrong types and values out of range stop with file,
// line and key). docs/hybrid.md lists the keys; scenes/ripples/huo2021_ripples.toml is the paper's case.
#include <string>
#include <vector>

#include "ripple_run.hpp"

namespace grainlab::ripples::hybrid {

struct HybridConfig {
  RippleOptions options;
  std::string text;  // the config as read
  // Its values as the run reads them (overrides applied; no comments, layout or duration), so a checkpoint
  // continues under a config edited only in those.
  std::string values;
};
// Throws InputError. `overrides`: command-line KEY=VALUE pairs that replace or add [hybrid] keys
// (ripples::apply_overrides); the config's text then records them.
HybridConfig parse_hybrid_config(const std::string& text, const std::string& path,
                                 const std::vector<std::string>& overrides = {});

// How the values of `other` (a config's text, or HybridConfig::values) differ from c's, key by key
// ("u_star: 45 there, 40 here"), durations aside; empty if they do not, or if `other` is not TOML.
std::string config_differences(const std::string& other, const HybridConfig& c);

}  // namespace grainlab::ripples::hybrid
