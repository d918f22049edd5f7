#pragma once
// Ensembles of independent runs. Run i draws its initial conditions from Rng(seed, i), so its result
// depends on i alone; under mpirun the runs are dealt out over the ranks (rank r takes i = r, r + size,
// ...) and gathered, so the table is the same on any number of ranks, and with none.
#include <cstddef>
#include <functional>
#include <vector>

namespace grainlab::validation {

using EnsembleProgress = std::function<void(std::size_t done, std::size_t total)>;

// run(i) returns `width` numbers for run i; the result has one row per run, in run order, on every rank.
std::vector<std::vector<double>> run_ensemble(std::size_t runs, std::size_t width,
                                              const std::function<std::vector<double>(std::size_t)>& run,
                                              const EnsembleProgress& progress = {});

// Mean, standard deviation and the 95 % interval of the mean (Student's t with n - 1 degrees of freedom:
// ensembles of 5 to 20 seeds are common here, for which t is 2.78 to 2.09, not the normal 1.96) of the
// finite values of a sample (NaN marks "undefined for this run" and is skipped). One value gives sd 0 and
// lo = hi = mean: callers print no interval for n = 1.
struct MeanInterval {
  std::size_t n = 0;
  double mean = 0, sd = 0, lo = 0, hi = 0;
  double half_width() const { return (hi - lo) / 2; }
};
MeanInterval mean_interval(const std::vector<double>& values);

// The two-sided 95 % quantile of Student's t with `dof` >= 1 degrees of freedom (12.706 for 1, 2.262 for 9,
// 1.960 in the limit); the half-width of mean_interval is t_975(n - 1) sd / sqrt(n).
double t_975(std::size_t dof);

// Median wall time and mean step count of an ensemble's runs (0 for none).
struct RunCost {
  double median_wall_seconds = 0, mean_steps = 0;
};
RunCost run_cost(std::vector<double> wall_seconds, const std::vector<double>& steps);

// A proportion k / n with its 95 % Wilson score interval.
struct Proportion {
  std::size_t k = 0, n = 0;
  double p = 0, lo = 0, hi = 1;
  double half_width() const { return (hi - lo) / 2; }
};
Proportion wilson_interval(std::size_t k, std::size_t n);

// z for a family of `m` two-sided 95 % statements (Bonferroni): a suite of many statistical checks
// must not fail by chance one time in two.
double family_z(std::size_t m);

// Student's t for the same family, for means of few samples (dof = n - 1 >= 1): family_t(1, dof) = t_975.
double family_t(std::size_t m, std::size_t dof);

// The least-squares line y = intercept + slope x through n >= 3 points, with the standard errors of both
// (from the scatter about the line, n - 2 degrees of freedom). Throws std::invalid_argument for fewer
// points, unequal lengths, or x all equal.
struct LineFit {
  double intercept = 0, slope = 0, intercept_se = 0, slope_se = 0;
};
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

// Throws needed for a 95 % interval of half-width h on a proportion near p (normal approximation).
double throws_for_half_width(double p, double h);

}  // namespace grainlab::validation
