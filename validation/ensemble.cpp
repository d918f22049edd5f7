#include "ensemble.hpp"

#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <stdexcept>

#include "parallel.hpp"

namespace grainlab::validation {

std::vector<std::vector<double>> run_ensemble(std::size_t runs, std::size_t width,
                                              const std::function<std::vector<double>(std::size_t)>& run,
                                              const EnsembleProgress& progress) {
  const std::size_t rank = parallel::rank(), ranks = parallel::size();
  std::vector<double> table(runs * width, 0.0);  // zeros from the other ranks: the sum is exact
  std::size_t done = 0;
  // Told at the start too, so that the first run done already gives an estimate of the time left.
  if (progress && runs > 0) progress(0, runs);
  for (std::size_t i = rank; i < runs; i += ranks) {
    const std::vector<double> row = run(i);
    if (row.size() != width) throw std::logic_error("ensemble run returned the wrong number of values");
    for (std::size_t c = 0; c < width; ++c) table[i * width + c] = row[c];
    ++done;
    if (progress) progress(std::min(runs, done * ranks), runs);  // this rank's share, scaled
  }
  parallel::sum_all(table);
  std::vector<std::vector<double>> rows(runs);
  for (std::size_t i = 0; i < runs; ++i)
    rows[i].assign(table.begin() + static_cast<std::ptrdiff_t>(i * width),
                   table.begin() + static_cast<std::ptrdiff_t>((i + 1) * width));
  return rows;
}

MeanInterval mean_interval(const std::vector<double>& values) {
  MeanInterval m;
  double sum = 0;
  for (double v : values)
    if (std::isfinite(v)) sum += v, ++m.n;
  if (m.n == 0) {
    m.mean = m.sd = m.lo = m.hi = std::nan("");
    return m;
  }
  m.mean = sum / m.n;
  double ss = 0;
  for (double v : values)
    if (std::isfinite(v)) ss += (v - m.mean) * (v - m.mean);
  m.sd = m.n > 1 ? std::sqrt(ss / (m.n - 1)) : 0;
  const double half = m.n > 1 ? t_975(m.n - 1) * m.sd / std::sqrt(static_cast<double>(m.n)) : 0.0;
  m.lo = m.mean - half, m.hi = m.mean + half;
  return m;
}

double t_975(std::size_t dof) {
  return family_t(1, dof);
}

Proportion wilson_interval(std::size_t k, std::size_t n) {
  Proportion r;
  r.k = k, r.n = n;
  if (n == 0) return r;
  const double z = 1.959963984540054, nn = static_cast<double>(n), p = k / nn;
  const double centre = (p + z * z / (2 * nn)) / (1 + z * z / nn);
  const double half = z / (1 + z * z / nn) * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn));
  r.p = p, r.lo = std::max(0.0, centre - half), r.hi = std::min(1.0, centre + half);
  return r;
}

double family_z(std::size_t m) {
  // Inverse normal tail by bisection on erfc: to 1e-10, plenty for an interval.
  const double alpha = 0.05 / static_cast<double>(std::max<std::size_t>(1, m));
  double lo = 0, hi = 10;
  for (int k = 0; k < 100; ++k) {
    const double mid = (lo + hi) / 2;
    (std::erfc(mid / std::sqrt(2.0)) > alpha ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

double family_t(std::size_t m, std::size_t dof) {
  if (dof == 0) throw std::invalid_argument("Student's t needs one or more degrees of freedom");
  const double alpha = 0.05 / static_cast<double>(std::max<std::size_t>(1, m));
  return boost::math::quantile(boost::math::students_t(static_cast<double>(dof)), 1 - alpha / 2);
}

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 3)
    throw std::invalid_argument("fit_line: needs three or more (x, y) points of equal count");
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    sxx += (x[i] - mx) * (x[i] - mx), sxy += (x[i] - mx) * (y[i] - my);
  if (!(sxx > 0)) throw std::invalid_argument("fit_line: every x is the same");
  LineFit f;
  f.slope = sxy / sxx, f.intercept = my - f.slope * mx;
  double ss = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (f.intercept + f.slope * x[i]);
    ss += r * r;
  }
  const double s2 = ss / (n - 2);
  f.slope_se = std::sqrt(s2 / sxx), f.intercept_se = std::sqrt(s2 * (1 / n + mx * mx / sxx));
  return f;
}

double throws_for_half_width(double p, double h) {
  const double z = 1.959963984540054;
  return std::ceil(z * z * p * (1 - p) / (h * h));
}

RunCost run_cost(std::vector<double> wall_seconds, const std::vector<double>& steps) {
  RunCost c;
  for (double s : steps) c.mean_steps += s / static_cast<double>(steps.size());
  if (!wall_seconds.empty()) {
    std::sort(wall_seconds.begin(), wall_seconds.end());
    c.median_wall_seconds = wall_seconds[wall_seconds.size() / 2];
  }
  return c;
}

}  // namespace grainlab::validation
