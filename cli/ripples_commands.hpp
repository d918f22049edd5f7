#pragma once
// `grainlab ripples ...`: the thesis's ripple models (Ch. V); so far Haff's worm model.
#include <CLI/CLI.hpp>
#include <cstdint>

namespace grainlab::cli {

struct RipplesCommands {
  int links = 10, start = 5, steps = 416, worms = 200, length = 2;
  double A = 0.6;
  std::size_t runs = 20000;
  std::uint64_t seed = 1;
  bool json = false;
  CLI::App *group = nullptr, *chain = nullptr, *ring = nullptr;
  void add(CLI::App& app);
  int dispatch() const;  // -1 if none of these ran
};

}  // namespace grainlab::cli
