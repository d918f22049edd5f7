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
};
// Throws InputError. `overrides`: command-line KEY=VALUE pairs that replace or add [hybrid] keys
// (ripples::apply_overrides); the config's text then records them.
HybridConfig parse_hybrid_config(const std::string& text, const std::string& path,
                                 const std::vector<std::string>& overrides = {});

}  // namespace grainlab::ripples::hybrid
