// Suite `loaded-die`: the thesis's loaded 2-D die thrown on every engine, p_h against the loading f and
// the restitution eps, beside the model of Appendix II.1 (both readings, die_model.hpp).
#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "die_model.hpp"
#include "ensemble.hpp"
#include "loaded_die.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

struct Cell {
  std::string engine;
  double f = 0, eps = 0;
  Proportion p_h;
  std::size_t uncaptured = 0;
  double mean_time = 0, seconds = 0;
};

double sigma(const Proportion& p) {
  return p.n ? std::sqrt(std::max(p.p * (1 - p.p), 1e-12) / p.n) : 1.0;
}

// Throws the die `throws` times; the raw throws go to the report's results.h5.
Cell run_cell(Report& report, const std::string& engine, double f, double eps, std::size_t throws,
              const SuiteOptions& o) {
  Cell c{engine, f, eps, {}, 0, 0, 0};
  const auto start = std::chrono::steady_clock::now();
  const auto rows = suite_ensemble(o, fmt::format("loaded-die-2d-{}-eps-{}-f-{}", engine, eps, f), throws, 2,
                                   [&](std::size_t i) {
                                     const DieThrow t = throw_die_2d(engine, Die2d{f, eps, 0.8}, 1987, i);
                                     return std::vector<double>{double(t.face_down), t.time};
                                   });
  std::size_t high_up = 0, captured = 0;
  for (const auto& row : rows) {
    if (row[0] < 0) {
      ++c.uncaptured;
      continue;
    }
    ++captured;
    high_up += (row[0] == 1 || row[0] == 2);
    c.mean_time += row[1];
  }
  c.p_h = wilson_interval(high_up, captured);
  c.mean_time = captured ? c.mean_time / captured : 0;
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.samples.push_back({fmt::format("loaded_die_2d/{}/eps_{}/f_{}", engine, eps, f),
                            "one row per throw (seed 1987, throw index = row): face down (0, 3 high faces "
                            "down; -1 not captured), capture time (s)",
                            {"face_down", "time_s"},
                            rows});
  return c;
}

// Every cell of the suite: each engine thrown at each restitution and loading.
struct Grid {
  std::vector<double> fs, epss;
  std::vector<std::string> engines;
  std::vector<Cell> cells;

  const Cell& at(const std::string& eng, double eps, double f) const {
    for (const Cell& c : cells)
      if (c.engine == eng && c.eps == eps && c.f == f) return c;
    throw std::logic_error("no such cell");
  }
};

// Fair die: p_h = 1/2 on every engine (all eps pooled), at family-wise 95 %.
void expect_fair(Report& r, const Grid& g) {
  const double zf = family_z(g.engines.size());
  for (const std::string& eng : g.engines) {
    std::size_t k = 0, n = 0;
    for (double eps : g.epss) k += g.at(eng, eps, 0.0).p_h.k, n += g.at(eng, eps, 0.0).p_h.n;
    const Proportion p = wilson_interval(k, n);
    r.expect_near("loaded-die/2d/fair-die", eng, p.p, 0.5, zf * std::sqrt(0.25 / std::max<std::size_t>(n, 1)),
                  fmt::format("fair 2-D die, {} throws over eps {}: fraction landing on faces 1-2; tolerance "
                              "{:.2f} sigma (95 % over {} engines)",
                              n, fmt::join(g.epss, ", "), zf, g.engines.size()));
  }
}

// Monotone in f, per engine and eps: consecutive steps do not reverse the overall trend beyond noise,
// and the trend itself (f = 0 to the largest f) is significant.
void expect_monotone(Report& r, const Grid& g) {
  const std::vector<double>& fs = g.fs;
  const double zm = family_z(g.engines.size() * g.epss.size() * (fs.size() - 1));
  for (const std::string& eng : g.engines)
    for (double eps : g.epss) {
      const double trend = g.at(eng, eps, fs.back()).p_h.p - g.at(eng, eps, fs.front()).p_h.p;
      const double sign = trend >= 0 ? 1 : -1;
      double worst = 0;
      for (std::size_t k = 0; k + 1 < fs.size(); ++k) {
        const Proportion &a = g.at(eng, eps, fs[k]).p_h, &b = g.at(eng, eps, fs[k + 1]).p_h;
        const double s = std::hypot(sigma(a), sigma(b));
        worst = std::max(worst, -sign * (b.p - a.p) / s);  // reversal in sigmas
      }
      r.expect_below(
          fmt::format("loaded-die/2d/monotone/eps-{}", eps), eng, worst, zm,
          fmt::format("largest step of p_h(f) against the trend ({} from f = {} to {}), in sigmas; "
                      "family-wise 95 % limit",
                      trend >= 0 ? "rising" : "falling", fs.front(), fs.back()));
    }
}

// One restitution's table and plot: every engine's p_h beside the model's two readings.
std::string eps_section(Report& r, const Grid& g, double eps) {
  std::string md = fmt::format("### eps = {}\n\n", eps) +
                   markdown_table_head({"f", "model (printed)", "model (geometric)"}, g.engines);
  PlotSpec plot{fmt::format("loaded_die_2d_eps{}.png", eps),
                fmt::format("Loaded 2-D die, eps = {}: p_h against loading", eps),
                "f",
                "p_h (high face up)",
                false,
                {}};
  PlotSpec::Series printed{"model, as printed", "dashed", {}, {}, {}},
      geometric{"model, die geometry", "line", {}, {}, {}};
  for (double f : g.fs) {
    const double mp = die_model(f, eps, DieModelVariant::Printed).p_h,
                 mg = die_model(f, eps, DieModelVariant::Geometric).p_h;
    printed.x.push_back(f), printed.y.push_back(mp), geometric.x.push_back(f), geometric.y.push_back(mg);
    md += fmt::format("| {} | {:.3f} | {:.3f} |", f, mp, mg);
    for (const auto& eng : g.engines) {
      const Cell& c = g.at(eng, eps, f);
      md += fmt::format(" {:.3f} +- {:.3f}{} |", c.p_h.p, c.p_h.half_width(),
                        c.uncaptured ? fmt::format(" ({} not captured)", c.uncaptured) : "");
    }
    md += "\n";
  }
  plot.series.push_back(printed);
  plot.series.push_back(geometric);
  for (const auto& eng : g.engines) {
    PlotSpec::Series s{eng, "points", {}, {}, {}};
    for (double f : g.fs) {
      const Cell& c = g.at(eng, eps, f);
      s.x.push_back(f), s.y.push_back(c.p_h.p), s.err.push_back(c.p_h.half_width());
    }
    plot.series.push_back(s);
  }
  r.plots.push_back(plot);
  return md + fmt::format("\n![eps {}]({})\n\n", eps, plot.file);
}

// Agreement between engines, cell by cell (paired throws; the interval of a difference is taken as
// unpaired, which is conservative).
std::string engine_agreement(const Grid& g) {
  std::string md =
      "### Engines against each other\n\n| engine pair | cells within 95 % of each other | largest "
      "difference (sigmas) at |\n|---|---|---|\n";
  const std::vector<std::string>& engines = g.engines;
  for (std::size_t a = 0; a < engines.size(); ++a)
    for (std::size_t b = a + 1; b < engines.size(); ++b) {
      std::size_t agree = 0, total = 0;
      double worst = 0;
      std::string where;
      for (double eps : g.epss)
        for (double f : g.fs) {
          const Proportion &pa = g.at(engines[a], eps, f).p_h, &pb = g.at(engines[b], eps, f).p_h;
          const double z = std::abs(pa.p - pb.p) / std::hypot(sigma(pa), sigma(pb));
          ++total, agree += z <= 1.96;
          if (z > worst) worst = z, where = fmt::format("eps {}, f {}: {:.3f} vs {:.3f}", eps, f, pa.p, pb.p);
        }
      md += fmt::format("| {} / {} | {} of {} | {:.1f} ({}) |\n", engines[a], engines[b], agree, total, worst,
                        where);
    }
  return md;
}

}  // namespace

void run_loaded_die_suite(Report& r, const SuiteOptions& o) {
  // Quick (CI): three loadings at two restitutions, 400 throws (+-0.05); full: the grid with a
  // 95 % interval of +-0.02 at p = 0.5 (the widest), 2401 throws per cell and engine.
  Grid g;
  g.fs = o.quick ? std::vector<double>{0.0, 0.2, 0.4} : std::vector<double>{0, 0.1, 0.2, 0.3, 0.4, 0.5};
  g.epss = o.quick ? std::vector<double>{0.5, 0.9} : std::vector<double>{0.3, 0.5, 0.7, 0.9};
  g.engines = engines_for_dimension(2);
  const std::size_t throws = o.quick ? 400 : static_cast<std::size_t>(throws_for_half_width(0.5, 0.02));
  for (const std::string& eng : g.engines)
    for (double eps : g.epss)
      for (double f : g.fs) {
        const Cell& c = g.cells.emplace_back(run_cell(r, eng, f, eps, throws, o));
        if (o.log)
          o.log(fmt::format(
              "loaded die 2-D on {}: eps {} f {}: p_h = {:.3f} [{:.3f}, {:.3f}] ({} throws, {} not "
              "captured, {:.1f} s)",
              eng, eps, f, c.p_h.p, c.p_h.lo, c.p_h.hi, throws, c.uncaptured, c.seconds));
      }
  expect_fair(r, g);
  expect_monotone(r, g);
  std::string md =
      "## Loaded die, 2-D (suite `loaded-die`)\n\n"
      "A 2 x 2 cm square, centre of mass moved a fraction f of the way to a corner, density 2 g/cm^2, "
      "die-plane restitution eps and friction 0.8, thrown from 3-5 cm with random orientation, +-50 cm/s "
      "and +-20 rad/s (Rng(1987, throw): the same throws on every engine), followed until captured by a face "
      "(docs/validation.md). p_h = fraction of captured throws with a high face up (a low face down), with "
      "its 95 % Wilson interval. Model: thesis eqs 2.A.1-2.A.4 as printed, and with the die's own potential "
      "(`grainlab die-model`).\n\n";
  for (double eps : g.epss) md += eps_section(r, g, eps);
  md += engine_agreement(g);
  md += "\nTime per cell (s), mean capture time (s):\n\n";
  for (const Cell& c : g.cells)
    md += fmt::format("- {} eps {} f {}: {:.1f} s, capture at {:.2f} s\n", c.engine, c.eps, c.f, c.seconds,
                      c.mean_time);
  r.markdown.push_back(md);
  run_loaded_die_3d(r, o);
}

}  // namespace grainlab::validation
