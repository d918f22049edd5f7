// `grainlab die-model`: the thesis's loaded-die model (Appendix II.1) at one (f, eps), and optionally a
// report with p_h against f for several eps (Fig. 2.7), in both readings of the equations.
#include "die_model_command.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "die_model.hpp"
#include "input_error.hpp"
#include "report.hpp"

namespace grainlab::cli {

namespace {

using validation::die_model;
using validation::DieModelVariant;

validation::Report figure_2_7() {
  validation::Report r;
  validation::PlotSpec plot{"die_model_p_h.png",
                            "Loaded 2-D die: p_h against loading (thesis Fig. 2.7)",
                            "f (fraction of the way from centre to corner)",
                            "p_h (high face up)",
                            false,
                            {}};
  std::string md =
      "# Loaded-die model (thesis Appendix II.1)\n\n"
      "p_h, the probability that a high face lands up, from eqs 2.A.1-2.A.4 as printed (high-face-down "
      "wells at f m_d g) and from the same capture argument with the die's own potential (wells at "
      "2 f m_d g a, a the half-side). Made by `grainlab die-model --plot DIR`.\n\n"
      "| eps | f | p_h printed | p_h geometric |\n|---|---|---|---|\n";
  for (const double eps : {0.1, 0.5, 0.7, 0.9, 0.99}) {
    validation::PlotSpec::Series printed{fmt::format("eps {} printed", eps), "dashed", {}, {}, {}};
    validation::PlotSpec::Series geometric{fmt::format("eps {} geometric", eps), "line", {}, {}, {}};
    for (int k = 0; k <= 50; ++k) {
      const double f = 0.6 * k / 50;
      printed.x.push_back(f), geometric.x.push_back(f);
      printed.y.push_back(die_model(f, eps, DieModelVariant::Printed).p_h);
      geometric.y.push_back(die_model(f, eps, DieModelVariant::Geometric).p_h);
      if (k % 10 == 0)
        md +=
            fmt::format("| {} | {:.1f} | {:.4f} | {:.4f} |\n", eps, f, printed.y.back(), geometric.y.back());
    }
    plot.series.push_back(printed);
    plot.series.push_back(geometric);
  }
  r.plots.push_back(plot);
  r.markdown.push_back(md);
  return r;
}

}  // namespace

int die_model_command(const DieModelArgs& a) {
  // (--f and --eps in [0, 1): checked as the command line is read)
  const auto printed = die_model(a.f, a.eps, DieModelVariant::Printed);
  const auto geometric = die_model(a.f, a.eps, DieModelVariant::Geometric);
  if (a.json) {
    auto row = [](const validation::DieModel& d) {
      return nlohmann::json{
          {"p_h", d.p_h}, {"E_l", d.e_low}, {"E_M", d.e_mid}, {"E_h", d.e_high}, {"high_well", d.high_well}};
    };
    fmt::print("{}\n", nlohmann::json{{"f", a.f},
                                      {"eps", a.eps},
                                      {"energy_unit", "m_d g a (a: half-side)"},
                                      {"printed", row(printed)},
                                      {"geometric", row(geometric)}}
                           .dump(2));
  } else {
    fmt::print(
        "loaded 2-D die, f = {}, eps = {} (thesis Appendix II.1; energies in m_d g a, a the half-side)\n",
        a.f, a.eps);
    fmt::print("p_h = {:.6f}   (eqs 2.A.1-2.A.4 as printed: high-face-down wells at f)\n", printed.p_h);
    fmt::print("p_h = {:.6f}   (the die's own potential: high-face-down wells at 2 f)\n", geometric.p_h);
    fmt::print("barriers: E_l = {:.6f}, E_M = {:.6f}, E_h = {:.6f} (printed) / {:.6f} (geometric)\n",
               printed.e_low, printed.e_mid, printed.e_high, geometric.e_high);
  }
  if (!a.plot_dir.empty()) {
    validation::write_report(figure_2_7(), a.plot_dir);
    if (!a.json) fmt::print("wrote {}/report.md and {}/die_model_p_h.png\n", a.plot_dir, a.plot_dir);
  }
  return 0;
}

}  // namespace grainlab::cli
