// Suite `tumbling-polygon`: the thesis's polygons dropped onto an incline on every 2-D engine (settled
// motion with intervals, sliding against Coulomb's law), the ideal pivot rule, and terminal rolling.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "ensemble.hpp"
#include "suites.hpp"
#include "tumbling_polygon.hpp"

namespace grainlab::validation {

namespace {

constexpr std::uint64_t kSeed = 1988;
constexpr double kRestitution = 0.5;

struct Cell {
  std::string engine, shape;
  double angle = 0, mu = 0;
  std::array<std::size_t, 4> count{};  // by Motion
  std::size_t runs = 0;
  double speed_sum = 0, speed_sq = 0;
  std::vector<double> sliding_acceleration;
  double seconds = 0;
  Proportion fraction(Motion m) const { return wilson_interval(count[static_cast<int>(m)], runs); }
  double mean_speed() const { return runs ? speed_sum / runs : 0; }
  double speed_error() const {  // 95 % half-width of the mean
    if (runs < 2) return 0;
    const double mean = mean_speed(), var = (speed_sq - runs * mean * mean) / (runs - 1);
    return t_975(runs - 1) * std::sqrt(std::max(var, 0.0) / runs);
  }
};

Cell run_cell(Report& r, const std::string& engine, std::size_t shape_index, double angle, double mu,
              std::size_t runs, const SuiteOptions& o) {
  const TumblingShape& shape = tumbling_shapes()[shape_index];
  Cell c{engine, shape.name, angle, mu, {}, 0, 0, 0, {}, 0};
  const auto start = std::chrono::steady_clock::now();
  auto rows =
      suite_ensemble(o, fmt::format("tumbling-polygon-{}-{}-incline-{}-mu-{}", engine, shape.name, angle, mu),
                     runs, 5, [&](std::size_t i) {
                       const TumbleRun t = tumble(engine, shape, {angle, mu, kRestitution}, kSeed, i);
                       return std::vector<double>{double(static_cast<int>(t.motion)), t.downslope_speed,
                                                  t.acceleration, t.turned, t.airborne};
                     });
  for (const auto& row : rows) {
    const auto m = static_cast<std::size_t>(row[0]);
    ++c.count[m], ++c.runs;
    c.speed_sum += row[1], c.speed_sq += row[1] * row[1];
    if (m == static_cast<std::size_t>(Motion::Sliding)) c.sliding_acceleration.push_back(row[2]);
  }
  c.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.samples.push_back(
      {fmt::format("tumbling_polygon/{}/{}/incline_{}/mu_{}", engine, shape.name, angle, mu),
       "one row per drop (seed 1988, drop index = row): motion (0 rest, 1 sliding, 2 rolling, 3 "
       "bouncing), mean downslope speed (cm/s), downslope acceleration (cm/s^2), |turn| (rad) "
       "and airborne fraction over the last second of 4 s",
       {"motion", "speed_cm_s", "acceleration_cm_s2", "turned_rad", "airborne"},
       std::move(rows)});
  return c;
}

// Checks that hold whatever the chaos: Coulomb's law for the runs that slide, and no rest on an incline
// steeper than the friction angle.
void coulomb_checks(Report& r, const std::vector<Cell>& cells, const std::vector<std::string>& engines) {
  for (const std::string& eng : engines) {
    double worst_cell = 0, worst_run = 0;
    std::string where = "no sliding runs", where_run;
    std::size_t resting_steep = 0, steep_runs = 0, too_short = 0;
    for (const Cell& c : cells) {
      if (c.engine != eng) continue;
      const double th = c.angle * M_PI / 180, expected = kG * (std::sin(th) - c.mu * std::cos(th));
      // Only where friction cannot hold the body (mu < tan th): those slides last the whole window. A
      // slide that decelerates ends inside it, often with a rock or a hop that is not sliding.
      if (c.mu >= std::tan(th)) continue;
      resting_steep += c.count[static_cast<int>(Motion::Rest)], steep_runs += c.runs;
      std::vector<double> a;
      for (double x : c.sliding_acceleration) {
        if (std::isnan(x)) {
          ++too_short;  // stopped within 0.01 s of the window's start: nothing to measure
          continue;
        }
        a.push_back(x);
        const double err = std::abs(x - expected) / (kG * std::sin(th));
        if (err >= worst_run)
          worst_run = err, where_run = fmt::format("{} at {} deg, mu {}: {:.1f}", c.shape, c.angle, c.mu, x);
      }
      if (a.empty()) continue;
      // The median run of the cell: a run still rocking from its landing is an outlier of the law's test,
      // not of the law (the worst single run is reported beside it).
      std::nth_element(a.begin(), a.begin() + a.size() / 2, a.end());
      const double median = a[a.size() / 2], err = std::abs(median - expected) / (kG * std::sin(th));
      if (err >= worst_cell)
        worst_cell = err, where = fmt::format(
                              "{} at {} deg, mu {}: median {:.1f} against {:.1f} cm/s^2 over {} "
                              "slides",
                              c.shape, c.angle, c.mu, median, expected, a.size());
    }
    r.expect_below(
        "tumbling-polygon/sliding-is-coulomb", eng, worst_cell, 0.02,
        fmt::format("largest |median a - g (sin th - mu cos th)| / (g sin th) over the cells where mu < "
                    "tan th ({}); worst single run {:.3f} ({}); {} stopped too soon to measure",
                    where, worst_run, where_run, too_short));
    r.expect_below("tumbling-polygon/no-rest-steeper-than-friction", eng, double(resting_steep), 0.0,
                   fmt::format("runs at rest where mu < tan(incline), of {}", steep_runs));
  }
}

std::string pivot_section(Report& r, const std::vector<std::string>& engines) {
  std::string md =
      "### The pivot rule\n\nA regular N-gon (circumradius 1.41 cm) pivoting on vertex A at w- = 20 rad/s "
      "lands its next vertex B flat on the plane in zero gravity (restitution 0.01, mu 10: no slip). Rigid-"
      "body impulse mechanics gives w+/w- = 1 - (m R^2/I_P)(1 - cos 2pi/N) for e = 0 (0.25 for the "
      "square, 11/17 for the hexagon). Tolerance: the rule's change from e = 0 to e = 0.01 plus 0.005.\n\n";
  md += markdown_table_head({"N", "rule (e = 0)", "rigid, e = 0.01"}, engines);
  for (int n : {4, 6}) {
    const double rule = pivot_ratio_rigid(n, 0.0), rigid = pivot_ratio_rigid(n, 0.01);
    md += fmt::format("| {} | {:.4f} | {:.4f} |", n, rule, rigid);
    for (const auto& eng : engines) {
      const double measured = pivot_ratio_measured(eng, n, 0.01, 10.0);
      md += fmt::format(" {:.4f} |", measured);
      if (engine_capabilities(eng).soft_contacts) continue;  // reported, not checked: see below
      r.expect_near(fmt::format("tumbling-polygon/pivot-rule/N-{}", n), eng, measured, rule,
                    std::abs(rule - rigid) + 0.005, "w+/w- of an inelastic no-slip pivot (zero gravity)");
    }
    md += "\n";
  }
  md += fmt::format(
      "\nThe native engine does not follow the rule: its contact is a spring, not an impulse. With the "
      "default elastic shear spring it keeps {:.2f} (square) and {:.2f} (hexagon) of the spin; damping the "
      "shear spring (k_s 1e9, damping_s 2e5) brings that to {:.2f} and {:.2f}, still above the rule. Smooth "
      "impacts (mu = 0) agree on every engine, so the difference is in how the soft tangential contact "
      "shares the impact; see docs/validation.md.\n\n",
      pivot_ratio_measured("native", 4, 0.01, 10.0), pivot_ratio_measured("native", 6, 0.01, 10.0),
      pivot_ratio_measured("native", 4, 0.01, 10.0, 0.0,
                           {"materials.rock.k_s=1e9", "materials.rock.damping_s=2e5", "accuracy.dt=4e-6"}),
      pivot_ratio_measured("native", 6, 0.01, 10.0, 0.0,
                           {"materials.rock.k_s=1e9", "materials.rock.damping_s=2e5", "accuracy.dt=4e-6"}));
  return md;
}

std::string rolling_section(const std::vector<std::string>& engines, bool quick) {
  std::string md =
      "### Terminal rolling speed\n\nThe same polygons (restitution 0.01, mu 1.0) started rolling on the "
      "incline; mean downslope speed over the last second of 3 s (cm/s), beside the ideal model (rigid "
      "pendulum pivots joined by rule impacts). \"lifts off\": late in each pivot the ideal model would "
      "need the plane to pull (w^2 R > g cos), so a real polygon leaves the plane before its next vertex "
      "lands; the faster it rolls, the more it hops and rolls like a wheel (the thesis's 'circle').\n\n";
  md += markdown_table_head({"N", "incline", "ideal model"}, engines);
  for (int n : {4, 6})
    for (double th : quick ? std::vector<double>{30} : std::vector<double>{20, 30, 40}) {
      const IdealRolling ideal = ideal_rolling(n, std::sqrt(2.0), th, kG);
      md += fmt::format("| {} | {} | {:.1f}{} |", n, th, ideal.speed, ideal.lifts_off ? " (lifts off)" : "");
      for (const auto& eng : engines)
        md += fmt::format(" {:.1f} |", measured_rolling_speed(eng, n, std::sqrt(2.0), th, 0.01, 1.0, 3.0));
      md += "\n";
    }
  return md + "\n";
}

}  // namespace

void run_tumbling_polygon_suite(Report& r, const SuiteOptions& o) {
  // Quick: square and hexagon at two inclines and two frictions, 24 drops; full: the grid, 200
  // drops per cell (fractions to +-0.07 at worst).
  const std::vector<std::size_t> shapes =
      o.quick ? std::vector<std::size_t>{0, 2} : std::vector<std::size_t>{0, 1, 2};
  const std::vector<double> angles = o.quick ? std::vector<double>{20, 40} : std::vector<double>{20, 30, 40};
  const std::vector<double> mus =
      o.quick ? std::vector<double>{0.2, 1.0} : std::vector<double>{0.2, 0.5, 1.0};
  const std::size_t runs = o.quick ? 24 : 200;
  const std::vector<std::string> engines = engines_for_dimension(2);

  std::vector<Cell> cells;
  for (const std::string& eng : engines)
    for (std::size_t s : shapes)
      for (double th : angles)
        for (double mu : mus) {
          cells.push_back(run_cell(r, eng, s, th, mu, runs, o));
          const Cell& c = cells.back();
          if (o.log)
            o.log(
                fmt::format("tumbling {} on {}: {} deg, mu {}: rest {} sliding {} rolling {} bouncing {} "
                            "({:.1f} s)",
                            c.shape, eng, th, mu, c.count[0], c.count[1], c.count[2], c.count[3], c.seconds));
        }
  coulomb_checks(r, cells, engines);

  std::string md = fmt::format(
      "## Tumbling polygon (suite `tumbling-polygon`)\n\n"
      "A 2 x 2 cm square, a 4 x 2 cm rectangle and an irregular hexagon (scenes/tumbling_hexagon.toml), "
      "density 2, dropped from rest with random orientation (Rng({}, drop)) from four times their size "
      "onto an incline (restitution {}, k_n = k_s = 1e8 on the native engine). After 3 s the last second is "
      "classified: **rolling** (turned through at least 2 pi/N), else **bouncing** (no vertex within 2 % of "
      "the size of the plane in at least 10 % of the samples), else **rest** (moved downslope less than "
      "1 cm/s on average: rocking in place counts as rest), else **sliding**. {} drops per cell; fractions "
      "with 95 % Wilson intervals; speed "
      "= mean downslope speed over that second, with its 95 % interval.\n\n",
      kSeed, kRestitution, runs);
  for (std::size_t s : shapes) {
    const std::string& name = tumbling_shapes()[s].name;
    md += fmt::format(
        "### {}\n\n| incline | mu | engine | rest | sliding | rolling | bouncing | speed (cm/s) |\n"
        "|---|---|---|---|---|---|---|---|\n",
        name);
    PlotSpec plot{fmt::format("tumbling_{}.png", name),
                  fmt::format("Tumbling {}: fraction rolling at mu = {}", name, mus.back()),
                  "incline (deg)",
                  "fraction rolling",
                  false,
                  {}};
    for (const std::string& eng : engines) {
      PlotSpec::Series series{eng, "points", {}, {}, {}};
      for (const Cell& c : cells) {
        if (c.engine != eng || c.shape != name) continue;
        md += fmt::format("| {} | {} | {} |", c.angle, c.mu, eng);
        for (Motion m : {Motion::Rest, Motion::Sliding, Motion::Rolling, Motion::Bouncing}) {
          const Proportion p = c.fraction(m);
          md += fmt::format(" {:.2f} +- {:.2f} |", p.p, p.half_width());
        }
        md += fmt::format(" {:.0f} +- {:.0f} |\n", c.mean_speed(), c.speed_error());
        if (c.mu == mus.back()) {
          const Proportion p = c.fraction(Motion::Rolling);
          series.x.push_back(c.angle), series.y.push_back(p.p), series.err.push_back(p.half_width());
        }
      }
      plot.series.push_back(series);
    }
    r.plots.push_back(plot);
    md += fmt::format("\n![{}]({})\n\n", name, plot.file);
  }
  md += pivot_section(r, engines);
  md += rolling_section(engines, o.quick);
  r.markdown.push_back(md);
}

}  // namespace grainlab::validation
