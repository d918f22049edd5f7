// `grainlab ripples run --config FILE [--out F.h5] [--json]`: any surface-evolving ripple model through the
// one interface (ripples/ripple_model.hpp): the config's table names the model.
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "ripple_model.hpp"
#include "ripples_commands.hpp"

namespace grainlab::cli {

using namespace grainlab::ripples;

int run_command(const RipplesCommands& a) {
  if (a.list_models) {
    for (const RippleModelEntry& m : ripple_models()) fmt::print("[{}]  {}\n", m.name, m.description);
    return 0;
  }
  if (a.config.empty()) throw InputError({"--config", 0}, "", "give a config (or --list for the models)");
  refuse_existing_out(a.out, a.force);
  std::ifstream in(a.config);
  if (!in) throw InputError({a.config, 0}, "", "cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  RippleModelRun run = create_ripple_model(text.str(), a.config, splash_hops);
  RippleModel& m = *run.model;
  const std::vector<std::string> keys = {
      "rms", "wavelength", "autocorrelation_wavelength", "height", "ripple_index", "stoss_deg", "lee_deg"};
  SampleTable h{
      "h", "surface height (grain diameters) per point (columns, dx apart) at each frame (rows)", {}, {}};
  for (std::size_t i = 0; i < m.surface().size(); ++i) h.columns.push_back(fmt::format("x{}", i));
  SampleTable history{"history",
                      "per frame: model time (" + m.time_unit() +
                          "), rms height, crest spacing, autocorrelation wavelength, crest height (grain "
                          "diameters), ripple index, stoss and lee slopes (deg)",
                      {"time"},
                      {}};
  for (const std::string& k : keys) history.columns.push_back(k);
  auto record = [&] {
    h.rows.push_back(m.surface());
    const auto d = m.diagnostics();
    std::vector<double> row{m.time()};
    for (const std::string& k : keys) row.push_back(d.at(k));
    history.rows.push_back(row);
  };
  record();
  for (int f = 0; f < run.frames; ++f) {
    m.advance(run.duration / run.frames);
    record();
  }
  if (!a.out.empty())
    write_sample_tables(a.out, {h, history},
                        {{"grainlab_version", GRAINLAB_VERSION},
                         {"model", run.name + " (grainlab ripples run)"},
                         {"config", run.text},
                         {"dx", fmt::format("{:.17g}", m.dx())},
                         {"time_unit", m.time_unit()},
                         {"units", "heights and x in grain diameters"}});
  if (!a.out.empty()) write_spacetime_plot(a.out, a.force, a.json);
  const auto d = m.diagnostics();
  if (a.json) {
    nlohmann::json j{{"model", run.name}, {"time", m.time()}, {"time_unit", m.time_unit()}, {"dx", m.dx()}};
    for (const auto& [k, v] : d) j[k] = v;
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print(
      "{} model, {} {}: wavelength {:.1f} d by autocorrelation, {:.1f} d between crests (every bump half the "
      "rms proud); crest height {:.1f} d, ripple index {:.1f} (crests), stoss {:.1f} / lee {:.1f} deg\n",
      run.name, m.time(), m.time_unit(), d.at("autocorrelation_wavelength"), d.at("wavelength"),
      d.at("height"), d.at("ripple_index"), d.at("stoss_deg"), d.at("lee_deg"));
  if (!a.out.empty()) fmt::print("wrote {} (h(x, t): {} frames)\n", a.out, h.rows.size());
  return 0;
}

}  // namespace grainlab::cli
