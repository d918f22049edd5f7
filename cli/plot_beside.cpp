#include "plot_beside.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>

#include "plot_script.hpp"

namespace grainlab::cli {

void draw_plot_beside(const std::string& h5, const std::string& suffix, const std::string& script,
                      const std::vector<std::string>& args, bool force, bool json, const std::string& what) {
  const std::string png = std::filesystem::path(h5).replace_extension("").string() + suffix + ".png";
  std::FILE* talk = json ? stderr : stdout;
  if (!force && std::filesystem::exists(png)) {
    fmt::print(talk, "kept {}: it exists (--force draws it again)\n", png);
    return;
  }
  const std::string why = validation::draw_png(script, args, png);
  if (why.empty())
    fmt::print(talk, "wrote {} ({})\n", png, what);
  else
    fmt::print(stderr, "no plot of {}: {}\n", what, why);
}

}  // namespace grainlab::cli
