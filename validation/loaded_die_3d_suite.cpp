// Suite `loaded-die`, 3-D part: a fair, a diagonally loaded and a drilled ("Monopoly") cube thrown on a
// plane on every 3-D engine; face frequencies with intervals, a chi-squared test of the fair die, the
// direction of the loaded die's bias, and how many throws would resolve the drilled die's bias.
#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cmath>

#include "ensemble.hpp"
#include "loaded_die.hpp"
#include "suites.hpp"

namespace grainlab::validation {

namespace {

struct Faces {
  std::array<std::size_t, 7> count{};  // by value up; [0] not captured
  std::size_t captured() const { return count[1] + count[2] + count[3] + count[4] + count[5] + count[6]; }
  double seconds = 0;
};

// Throws `die` n times on `engine`; the raw throws go to the report's results.h5 as `name`/engine.
Faces throw_many(Report& report, const std::string& name, const std::string& engine, const Die3d& die,
                 std::size_t n, const SuiteOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  auto rows = suite_ensemble(o, fmt::format("loaded-die-3d-{}-{}", name, engine), n, 2, [&](std::size_t i) {
    const DieThrow3d t = throw_die_3d(engine, die, 2026, i);
    return std::vector<double>{double(t.value_up), t.time};
  });
  Faces f;
  for (const auto& r : rows) ++f.count[static_cast<std::size_t>(r[0])];
  report.samples.push_back({"loaded_die_3d/" + name + "/" + engine,
                            "one row per throw (seed 2026, throw index = row): value up (0: not captured), "
                            "capture time (s)",
                            {"value_up", "time_s"},
                            std::move(rows)});
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return f;
}

// Upper tail of the chi-squared distribution with 5 degrees of freedom (closed form for odd k).
double chi2_5_upper(double x) {
  const double s = std::sqrt(x);
  return std::erfc(s / std::sqrt(2.0)) + std::sqrt(2 / M_PI) * std::exp(-x / 2) * (s + x * s / 3);
}

std::string row(const std::string& what, const std::string& eng, const Faces& f) {
  std::string s = fmt::format("| {} | {} |", what, eng);
  const double n = static_cast<double>(std::max<std::size_t>(1, f.captured()));
  for (int v = 1; v <= 6; ++v) {
    const Proportion p = wilson_interval(f.count[v], f.captured());
    s += fmt::format(" {:.4f} +- {:.4f} |", f.count[v] / n, p.half_width());
  }
  return s + fmt::format(" {} | {} | {:.0f} s |\n", f.captured(), f.count[0], f.seconds);
}

}  // namespace

void run_loaded_die_3d(Report& r, const SuiteOptions& o) {
  const std::size_t n = o.quick ? 300 : 20000;
  const double s = 0.2;  // loaded die: centre of mass at (s, s, s), a fifth of the way to a corner
  Die3d fair, loaded;
  fair.eps = loaded.eps = 0.5;
  for (double& c : loaded.com) c = s;
  const Die3d drilled = drilled_die(0.5, 0.8);
  const std::vector<std::string> engines = engines_for_dimension(3);

  std::string md = fmt::format(
      "## Loaded die, 3-D\n\n"
      "A 2 cm cube (density 2 g/cm^3, restitution 0.5, friction 0.8) thrown onto a plane from 3-5 cm with a "
      "uniformly random orientation, +-50 cm/s and +-20 rad/s per axis (Rng(2026, throw), the same throws on "
      "every engine), followed until captured by a face. Faces: 1 on -z, 6 on +z, 2/5 on -y/+y, 3/4 on "
      "-x/+x. Loaded: centre of mass at ({0}, {0}, {0}) cm, so faces 4, 5, 6 are the low ones and 3, 2, 1 "
      "should come up more often. Drilled: 21 pips 0.06 cm deep, radius 0.15 cm, removed; centre of mass "
      "({1:.2e}, {2:.2e}, {3:.2e}) cm.\n\n"
      "| die | engine | 1 | 2 | 3 | 4 | 5 | 6 | captured | not captured | time "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|\n",
      s, drilled.com[0], drilled.com[1], drilled.com[2]);
  const double zf = family_z(engines.size());
  std::string estimate;
  for (const std::string& eng : engines) {
    const Faces f0 = throw_many(r, "fair", eng, fair, n, o), f1 = throw_many(r, "loaded", eng, loaded, n, o),
                f2 = throw_many(r, "drilled", eng, drilled, n, o);
    if (o.log)
      o.log(fmt::format("loaded die 3-D on {}: {} throws each of the fair, loaded and drilled die ({:.0f} s)",
                        eng, n, f0.seconds + f1.seconds + f2.seconds));
    md += row("fair", eng, f0) + row("loaded", eng, f1) + row("drilled", eng, f2);
    // Fair die: chi-squared against uniform faces, 5 degrees of freedom, family-wise 95 % over engines.
    const double expected = f0.captured() / 6.0;
    double chi2 = 0;
    for (int v = 1; v <= 6; ++v)
      chi2 += (f0.count[v] - expected) * (f0.count[v] - expected) / std::max(expected, 1.0);
    r.expect_below(
        "loaded-die/3d/fair-uniform", eng, -std::log10(std::max(chi2_5_upper(chi2), 1e-300)),
        -std::log10(0.05 / engines.size()),
        fmt::format("fair cube, {} throws: chi^2 = {:.2f} (5 dof), p = {:.3f}; value: -log10 p, limit "
                    "family-wise 95 % over {} engines",
                    f0.captured(), chi2, chi2_5_upper(chi2), engines.size()));
    r.expect_below("loaded-die/3d/all-captured", eng, double(f0.count[0] + f1.count[0] + f2.count[0]), 0.0,
                   "throws not captured by a face within the time limit");
    // Loaded die: the high faces' opposites (1, 2, 3) come up more than half the time.
    const Proportion low_down = wilson_interval(f1.count[1] + f1.count[2] + f1.count[3], f1.captured());
    const double sigma = std::sqrt(0.25 / std::max<std::size_t>(1, f1.captured()));
    r.expect_below(
        "loaded-die/3d/loaded-bias", eng, -(low_down.p - 0.5) / sigma, -zf,
        fmt::format("loaded cube: P(1, 2 or 3 up) = {:.4f} [{:.4f}, {:.4f}]; value: minus its excess "
                    "over 1/2 in sigmas (must exceed {:.2f} sigmas)",
                    low_down.p, low_down.lo, low_down.hi, zf));
    // The drilled die: a linear response of P(value up) to the centre of mass's displacement along that
    // value's axis, calibrated on the loaded die (thesis: "the linear relation between probability and
    // displacement"), predicts its excess of sixes.
    const double n1 = std::max<std::size_t>(1, f1.captured());
    const double slope =
        ((f1.count[1] + f1.count[2] + f1.count[3]) - (f1.count[4] + f1.count[5] + f1.count[6])) / n1 / 3 /
        (2 * s);  // per cm of displacement, per axis: (P(low down) - P(high down)) / 2s
    const double slope_sigma = std::sqrt(1.0 / n1) / 3 / (2 * s);
    const double excess = slope * std::abs(drilled.com[2]);  // P(6) - 1/6 predicted
    const double p6 = 1.0 / 6,
                 n_needed = excess > 0 ? 1.96 * 1.96 * p6 * (1 - p6) / (excess * excess) : HUGE_VAL;
    const Proportion six = wilson_interval(f2.count[6], f2.captured());
    estimate += fmt::format(
        "- {}: slope {:.3f} +- {:.3f} per cm; predicted P(6) - 1/6 = {:.2e} ({:.2f} % more sixes); a 95 % "
        "interval that narrow needs about {:.2g} throws (2 sigma of the slope: {:.2g} to {:.2g}); measured "
        "P(6) = {:.4f} [{:.4f}, {:.4f}] in {} throws\n",
        eng, slope, slope_sigma, excess, 100 * excess / p6, n_needed,
        1.96 * 1.96 * p6 * (1 - p6) /
            std::pow(std::max(1e-9, (slope + 2 * slope_sigma) * std::abs(drilled.com[2])), 2),
        1.96 * 1.96 * p6 * (1 - p6) /
            std::pow(std::max(1e-9, (slope - 2 * slope_sigma) * std::abs(drilled.com[2])), 2),
        six.p, six.lo, six.hi, six.n);
  }
  md +=
      "\nThe drilled die's excess of sixes (thesis: about 0.5 % more often), from each engine's loaded-die "
      "response scaled to the drilled die's displacement toward the one:\n\n" +
      estimate;
  r.markdown.push_back(md);
}

}  // namespace grainlab::validation
