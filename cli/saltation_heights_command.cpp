// `grainlab saltation heights`: Fig. 4.22, the height grains of each size reach when launched into a
// sediment-free wind (docs/saltation.md, "Fig. 4.22").
#include <fmt/format.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "saltation_commands.hpp"
#include "saltation_heights.hpp"

namespace grainlab::cli {

namespace fs = std::filesystem;
using saltation::CleanWindLaunch;

namespace {

std::string heights_csv(const std::vector<CleanWindLaunch>& launches) {
  std::string csv =
      "diameter_cm,angle_deg,v_oy_cm_s,height_cm,length_cm,time_s,impact_vx_cm_s,impact_vy_cm_s,vacuum_"
      "height_cm\n";
  for (const CleanWindLaunch& l : launches)
    csv +=
        fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", l.diameter,
                    l.angle, l.v_oy, l.height, l.length, l.time, l.impact_vx, l.impact_vy, l.vacuum_height);
  return csv;
}

nlohmann::json heights_json(const saltation::CleanWindSpec& s, const std::vector<CleanWindLaunch>& launches) {
  nlohmann::json rows = nlohmann::json::array();
  for (const CleanWindLaunch& l : launches)
    rows.push_back({{"diameter", l.diameter},
                    {"angle", l.angle},
                    {"v_oy", l.v_oy},
                    {"height", l.height},
                    {"length", l.length},
                    {"time", l.time},
                    {"impact_velocity", {l.impact_vx, l.impact_vy}},
                    {"vacuum_height", l.vacuum_height}});
  nlohmann::json exponents = nlohmann::json::array();
  for (double d : s.diameters)
    for (double a : s.angles) {
      const double e = saltation::height_exponent_at_top(launches, d, a);
      exponents.push_back({{"diameter", d},
                           {"angle", a},
                           {"exponent", std::isfinite(e) ? nlohmann::json(e) : nlohmann::json(nullptr)}});
    }
  return {{"grainlab_version", GRAINLAB_VERSION}, {"u_star", s.u_star},    {"roughness", s.roughness},
          {"grain_density", s.grain_density},     {"units", "cm, s, deg"}, {"launches", rows},
          {"height_exponent_at_top", exponents}};
}

}  // namespace

int heights_command(const SaltationCommands& a) {
  const saltation::CleanWindSpec& s = a.heights_spec;
  if (s.speeds.empty()) throw InputError({"--speeds", 0}, "", "give at least one launch speed");
  if (!a.heights_out.empty() && fs::exists(a.heights_out) && !fs::is_empty(a.heights_out) && !a.force)
    throw InputError({"--out", 0}, a.heights_out,
                     "exists and is not empty; pass --force to replace its files");
  const std::vector<CleanWindLaunch> launches = saltation::clean_wind_heights(s);
  const nlohmann::json out = heights_json(s, launches);
  if (!a.heights_out.empty()) {
    fs::create_directories(a.heights_out);
    write_file_atomically((fs::path(a.heights_out) / "heights.csv").string(), heights_csv(launches));
    write_file_atomically((fs::path(a.heights_out) / "heights.json").string(), out.dump(2));
    validation::write_plots({validation::clean_wind_height_plot(launches, "fig4_22.png")}, a.heights_out);
  }
  if (a.heights_json) {
    fmt::print("{}\n", out.dump(2));
    return 0;
  }
  fmt::print(
      "Heights reached in a sediment-free wind (u* = {:g} cm/s, roughness {:g} cm; thesis Fig. 4.22)\n\n{}",
      s.u_star, s.roughness, validation::clean_wind_height_table(launches));
  for (double d : s.diameters)
    for (double angle : s.angles)
      fmt::print("d = {:g} cm at {:g} deg: d ln h / d ln v_oy at the fastest launches {:.2f} (vacuum 2)\n", d,
                 angle, saltation::height_exponent_at_top(launches, d, angle));
  if (!a.heights_out.empty())
    fmt::print("wrote {}/heights.csv and {}/fig4_22.png\n", a.heights_out, a.heights_out);
  return 0;
}

}  // namespace grainlab::cli
