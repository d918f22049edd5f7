// `grainlab saltation study`: the wind-driven model over planets, grain sizes and u*, with its impact
// threshold and the classic flux laws beside it (docs/saltation.md, "Other planets").
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "h5_output.hpp"
#include "input_error.hpp"
#include "report.hpp"
#include "saltation_commands.hpp"
#include "study.hpp"

namespace grainlab::cli {

namespace fs = std::filesystem;
using namespace grainlab::saltation;

namespace {

struct StudyRow {
  std::string planet;
  double d = 0, u_t = 0, u_star = 0;
  WindModelResult r;
};

WindModelOptions options_for(const SaltationCommands& a, const Planet& p, double d) {
  WindModelOptions o;
  o.g = p.g, o.fluid.density = p.air_density, o.fluid.viscosity = p.viscosity;
  o.grain.radius = d / 2, o.grain.density = a.grain_density;
  o.buoyancy = true;
  // Launch bins follow the splash's velocity scale, so every planet and size gets the same resolution.
  o.dv *= std::sqrt(p.g * d / (981 * 0.025));
  // Thin air (Mars) launches far faster than sqrt(g d) suggests: twice the thesis's grid.
  o.bins = 160;
  return o;
}

void check_study_input(const SaltationCommands& a) {
  if (a.study_out.empty()) throw InputError({"--out", 0}, "", "the study needs an output folder");
  if (fs::exists(a.study_out) && !a.force)
    throw InputError({"--out", 0}, a.study_out, "exists; pass --force to replace it");
  for (const std::string& p : a.planets) try {
      planet_preset(p);
    } catch (const std::invalid_argument& e) {
      throw InputError({"--planet", 0}, p, "unknown planet; known: earth, mars, venus");
    }
}

std::vector<validation::PlotSpec> study_plots(const std::vector<StudyRow>& rows, const SaltationCommands& a) {
  using validation::PlotSpec;
  PlotSpec flux{"study_flux.png",
                "Mass flux: grainlab (solid) and the classic laws (dashed)",
                "u* (cm/s)",
                "Q (g/(cm s))",
                true,
                {}};
  flux.logy = true;
  PlotSpec hop{"study_hop_height.png", "Mean hop height", "u* (cm/s)", "height (cm)", true, {}};
  PlotSpec eff{"study_ustar_eff.png",
               "u*_eff: the shear stress the grains leave the air at the bed",
               "u* (cm/s)",
               "u*_eff (cm/s)",
               true,
               {}};
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    const std::string label = fmt::format("{} d = {:g} cm", rows[i].planet, rows[i].d);
    PlotSpec::Series q{label, "linepoints", {}, {}, {}}, h{label, "linepoints", {}, {}, {}},
        e{label, "linepoints", {}, {}, {}};
    for (; j < rows.size() && rows[j].planet == rows[i].planet && rows[j].d == rows[i].d; ++j) {
      if (!rows[j].r.converged) continue;
      q.x.push_back(rows[j].u_star), q.y.push_back(rows[j].r.mass_flux);
      h.x.push_back(rows[j].u_star), h.y.push_back(rows[j].r.mean_hop_height);
      e.x.push_back(rows[j].u_star), e.y.push_back(rows[j].r.u_star_eff);
    }
    flux.series.push_back(q), hop.series.push_back(h), eff.series.push_back(e);
    // The laws for the first grain size of each planet (more would crowd the plot).
    if (rows[i].d == a.diameters.front()) {
      const Planet p = planet_preset(rows[i].planet);
      for (const FluxLaw& law : classic_flux_laws()) {
        PlotSpec::Series s{fmt::format("{} ({})", law.name, rows[i].planet), "dashed", {}, {}, {}};
        for (std::size_t k = i; k < j; ++k)
          s.x.push_back(rows[k].u_star), s.y.push_back(law.q(rows[k].u_star, rows[k].u_t, p.air_density,
                                                             a.grain_density, p.g, rows[k].d));
        flux.series.push_back(s);
      }
    }
    i = j;
  }
  return {flux, hop, eff};
}

std::string study_table(const std::vector<StudyRow>& rows, const SaltationCommands& a) {
  std::string csv =
      "planet,diameter_cm,u_star_t,u_star,u_star_eff,mass_flux,mean_hop_height,mean_hop_length,"
      "impact_vx,impact_vy,converged,iterations";
  for (const FluxLaw& law : classic_flux_laws()) csv += ",Q " + law.name;
  csv += "\n";
  for (const StudyRow& s : rows) {
    csv +=
        fmt::format("{},{},{:.4g},{:.4g},{:.4g},{:.5g},{:.4g},{:.4g},{:.4g},{:.4g},{},{}", s.planet, s.d,
                    s.u_t, s.u_star, s.r.u_star_eff, s.r.mass_flux, s.r.mean_hop_height, s.r.mean_hop_length,
                    s.r.mean_impact_vx, s.r.mean_impact_vy, s.r.converged, s.r.iterations);
    const Planet p = planet_preset(s.planet);
    for (const FluxLaw& law : classic_flux_laws())
      csv += fmt::format(",{:.5g}", law.q(s.u_star, s.u_t, p.air_density, a.grain_density, p.g, s.d));
    csv += "\n";
  }
  return csv;
}

nlohmann::json row_json(const StudyRow& s) {
  return {{"planet", s.planet},
          {"diameter", s.d},
          {"u_star_t", s.u_t},
          {"u_star", s.u_star},
          {"u_star_eff", s.r.u_star_eff},
          {"mass_flux", s.r.mass_flux},
          {"mean_hop_height", s.r.mean_hop_height},
          {"mean_hop_length", s.r.mean_hop_length},
          {"impact_velocity", {s.r.mean_impact_vx, s.r.mean_impact_vy}},
          {"converged", s.r.converged},
          {"failure", s.r.failure},
          {"iterations", s.r.iterations},
          {"wall_seconds", s.r.wall_seconds}};
}

StudyRow row_from_json(const nlohmann::json& j) {
  StudyRow s{j.at("planet").get<std::string>(),
             j.at("diameter").get<double>(),
             j.at("u_star_t").get<double>(),
             j.at("u_star").get<double>(),
             {}};
  s.r.u_star_eff = j.at("u_star_eff").get<double>(), s.r.mass_flux = j.at("mass_flux").get<double>();
  s.r.mean_hop_height = j.at("mean_hop_height").get<double>();
  s.r.mean_hop_length = j.at("mean_hop_length").get<double>();
  s.r.mean_impact_vx = j.at("impact_velocity").at(0).get<double>();
  s.r.mean_impact_vy = j.at("impact_velocity").at(1).get<double>();
  s.r.converged = j.at("converged").get<bool>(), s.r.failure = j.at("failure").get<std::string>();
  s.r.iterations = j.at("iterations").get<int>(), s.r.wall_seconds = j.at("wall_seconds").get<double>();
  return s;
}

// What a checkpoint must agree on to be resumed.
nlohmann::json study_options(const SaltationCommands& a) {
  return {{"case", a.study_case},
          {"planets", a.planets},
          {"diameters", a.diameters},
          {"ustar_factors", a.ustar_factors},
          {"grain_density", a.grain_density}};
}

// A checkpoint to resume from: its thresholds and runs, after checking it was made with the same options.
nlohmann::json read_checkpoint(const std::string& path, const SaltationCommands& a) {
  std::ifstream in(path);
  if (!in) throw InputError({"--restart", 0}, path, "cannot be read");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
    if (j.at("kind").get<std::string>() != "grainlab saltation study checkpoint")
      throw InputError({path, 0}, "kind", "is not a saltation study checkpoint");
    if (j.at("options") != study_options(a))
      throw InputError({path, 0}, "options",
                       "were " + j.at("options").dump() + "; this command has " + study_options(a).dump());
    for (const auto& r : j.at("runs")) row_from_json(r);  // every row must read
  } catch (const nlohmann::json::exception& e) {
    throw InputError({path, 0}, "", std::string("is not a readable checkpoint: ") + e.what());
  }
  return j;
}

}  // namespace

int study_command(const SaltationCommands& a) {
  check_study_input(a);
  // Resuming: the checkpoint's thresholds and finished runs are taken as they are (each run is
  // deterministic, so the finished study is the same as one made in a single go).
  nlohmann::json done_runs = nlohmann::json::array(), thresholds = nlohmann::json::array();
  if (!a.study_restart.empty()) {
    const nlohmann::json c = read_checkpoint(a.study_restart, a);
    done_runs = c.at("runs"), thresholds = c.at("thresholds");
  }
  const std::string checkpoint = a.study_out + ".checkpoint.json";
  std::vector<StudyRow> rows;
  std::size_t runs_done = 0;
  int fresh = 0;
  auto save = [&] {
    nlohmann::json runs = nlohmann::json::array();
    for (const StudyRow& r : rows) runs.push_back(row_json(r));
    write_file_atomically(checkpoint, nlohmann::json{{"kind", "grainlab saltation study checkpoint"},
                                                     {"options", study_options(a)},
                                                     {"thresholds", thresholds},
                                                     {"runs", runs}}
                                          .dump(1));
  };
  for (const std::string& name : a.planets) {
    const Planet p = planet_preset(name);
    for (double d : a.diameters) {
      WindModelOptions o = options_for(a, p, d);
      const double s = std::sqrt(p.g * d / (981 * 0.025));
      const SplashKernel splash = kernel_of(scaled(table_4_3(a.study_case), s));
      double u_t = -1;
      for (const auto& t : thresholds)
        if (t.at("planet") == name && t.at("diameter").get<double>() == d)
          u_t = t.at("u_star_t").get<double>();
      if (u_t < 0) {
        u_t = impact_threshold(o, splash);
        thresholds.push_back({{"planet", name}, {"diameter", d}, {"u_star_t", u_t}});
      }
      if (!a.quiet) fmt::print(stderr, "{} d = {:g} cm: impact threshold u*_t = {:.1f} cm/s\n", name, d, u_t);
      if (u_t <= 0) continue;
      for (double f : a.ustar_factors) {
        if (runs_done < done_runs.size()) {  // finished before the checkpoint
          rows.push_back(row_from_json(done_runs[runs_done++]));
          continue;
        }
        if (a.study_stop_after > 0 && fresh >= a.study_stop_after) {
          save();
          fmt::print(stderr, "stopped after {} new runs; resume with --restart {}\n", fresh, checkpoint);
          return 0;
        }
        o.u_star = f * u_t;
        StudyRow row{name, d, u_t, o.u_star, solve_wind_model(o, splash)};
        if (!a.quiet && !row.r.failure.empty())
          fmt::print(stderr, "  u* = {:.1f}: no steady state: {}\n", o.u_star, row.r.failure);
        else if (!a.quiet)
          fmt::print(stderr, "  u* = {:.1f}: {} u*_eff {:.1f}, Q {:.3g} g/(cm s), hop {:.2f} cm ({:.1f} s)\n",
                     o.u_star, row.r.converged ? "" : "NOT converged,", row.r.u_star_eff, row.r.mass_flux,
                     row.r.mean_hop_height, row.r.wall_seconds);
        rows.push_back(std::move(row));
        ++fresh;
        save();
      }
    }
  }
  // Everything goes to a temporary folder that replaces --out at the end.
  const std::string tmp = a.study_out + ".partial";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  write_file_atomically(tmp + "/study.csv", study_table(rows, a));
  nlohmann::json rows_json = nlohmann::json::array();
  for (const StudyRow& s : rows) {
    nlohmann::json r = row_json(s);
    r.erase("wall_seconds");  // the only machine-dependent number: kept out so files compare
    rows_json.push_back(r);
  }
  nlohmann::json laws = nlohmann::json::array();
  for (const FluxLaw& law : classic_flux_laws())
    laws.push_back({{"name", law.name}, {"formula", law.formula}});
  const nlohmann::json out{{"grainlab_version", GRAINLAB_VERSION},
                           {"splash", fmt::format("Table 4.3 CASE {} scaled by sqrt(g d)", a.study_case)},
                           {"grain_density", a.grain_density},
                           {"thresholds", thresholds},
                           {"runs", rows_json},
                           {"flux_laws", laws}};
  write_file_atomically(tmp + "/study.json", out.dump(2));
  validation::write_plots(study_plots(rows, a), tmp);
  fs::remove_all(a.study_out);
  fs::rename(tmp, a.study_out);
  fs::remove(checkpoint);
  if (a.study_json)
    fmt::print("{}\n", out.dump(2));
  else
    fmt::print("{} runs; table {}/study.csv, plots {}/study_*.png\n", rows.size(), a.study_out, a.study_out);
  return 0;
}

}  // namespace grainlab::cli
