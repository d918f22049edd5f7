#include "surface_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

namespace grainlab::ripples {

namespace {
double at(const std::vector<double>& y, long i) {
  const long n = static_cast<long>(y.size());
  return y[static_cast<std::size_t>(((i % n) + n) % n)];
}
}  // namespace

std::vector<double> tombrello_smooth(const std::vector<double>& y, int n, double sigma) {
  std::vector<double> s(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    double num = 0, den = 0;
    for (long j = static_cast<long>(i) - n; j <= static_cast<long>(i) + n; ++j) {
      const double d = y[i] - at(y, j), w = std::exp(-d * d / (2 * sigma * sigma));
      num += at(y, j) * w, den += w;
    }
    s[i] = num / den;
  }
  return s;
}

std::vector<double> length_scale_distribution(const std::vector<double>& h, int max_lag, double sigma) {
  std::vector<double> f(static_cast<std::size_t>(max_lag), 0.0);
  double total = 0;
  for (int l = 1; l <= max_lag; ++l) {
    double s = 0;
    for (std::size_t j = 0; j < h.size(); ++j) {
      const double d = h[j] - at(h, static_cast<long>(j) + l);
      s += std::exp(-d * d / (2 * sigma * sigma));
    }
    f[static_cast<std::size_t>(l - 1)] = s, total += s;
  }
  if (total > 0)
    for (double& v : f) v /= total;
  return f;
}

int length_scale_peak(const std::vector<double>& f) {
  std::size_t k = 1;
  while (k < f.size() && f[k] <= f[k - 1]) ++k;  // down to the first minimum
  if (k >= f.size()) return 0;
  std::size_t best = k;
  for (std::size_t j = k; j < f.size(); ++j)
    if (f[j] > f[best]) best = j;
  return static_cast<int>(best) + 1;
}

std::vector<double> power_spectrum(const std::vector<double>& h) {
  const std::size_t n = h.size();
  double mean = 0;
  for (double v : h) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> p(n / 2);
  for (std::size_t k = 1; k <= n / 2; ++k) {
    std::complex<double> s = 0;
    for (std::size_t j = 0; j < n; ++j)
      s += (h[j] - mean) *
           std::polar(1.0, -2 * M_PI * static_cast<double>(k * j % n) / static_cast<double>(n));
    p[k - 1] = std::norm(s);
  }
  return p;
}

double autocorrelation_wavelength(const std::vector<double>& h) {
  const std::size_t n = h.size();
  double mean = 0;
  for (double v : h) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> c(n / 2);
  for (std::size_t l = 0; l < n / 2; ++l) {
    double s = 0;
    for (std::size_t j = 0; j < n; ++j) s += (h[j] - mean) * (at(h, static_cast<long>(j + l)) - mean);
    c[l] = s;
  }
  std::size_t k = 1;
  while (k < c.size() && c[k] > 0) ++k;  // first zero crossing
  // The first maximum that reaches half the highest one: later maxima of a periodic surface repeat the
  // first (multiples of the wavelength), and small wiggles are not a wavelength.
  double best = 0;
  for (std::size_t l = k; l + 1 < c.size(); ++l)
    if (c[l] > c[l - 1] && c[l] >= c[l + 1]) best = std::max(best, c[l]);
  for (std::size_t l = k; l + 1 < c.size(); ++l)
    if (c[l] > c[l - 1] && c[l] >= c[l + 1] && c[l] >= 0.5 * best && best > 0) return static_cast<double>(l);
  return 0;
}

double rms_height(const std::vector<double>& y) {
  if (y.empty()) return 0;
  double mean = 0, sum = 0;
  for (double v : y) mean += v;
  mean /= static_cast<double>(y.size());
  for (double v : y) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / static_cast<double>(y.size()));
}

SurfaceShape surface_shape(const std::vector<double>& y, double dx, double min_relief) {
  SurfaceShape s;
  const std::size_t n = y.size();
  if (n < 4) return s;
  s.rms = rms_height(y);
  // Two passes round the ring: the first finds the phase, the second records (index, height) extremes.
  std::vector<std::pair<std::size_t, double>> ext;
  int dir = 0;
  double lo = y[0], hi = y[0];
  std::size_t lo_i = 0, hi_i = 0;
  for (std::size_t i = 1; i < 2 * n; ++i) {
    const double v = y[i % n];
    if (v > hi) hi = v, hi_i = i;
    if (v < lo) lo = v, lo_i = i;
    if (dir >= 0 && hi - v > min_relief) {  // a crest at hi_i
      if (i >= n) ext.push_back({hi_i, hi});
      dir = -1, lo = v, lo_i = i;
    } else if (dir <= 0 && v - lo > min_relief) {  // a trough at lo_i
      if (i >= n) ext.push_back({lo_i, lo});
      dir = 1, hi = v, hi_i = i;
    }
  }
  double spacing = 0, height = 0, stoss = 0, lee = 0;
  int rises = 0, falls = 0;
  for (std::size_t k = 1; k < ext.size(); ++k) {
    const auto [x0, y0] = ext[k - 1];
    const auto [x1, y1] = ext[k];
    const double angle = std::atan(std::abs(y1 - y0) / ((x1 - x0) * dx)) * 180 / M_PI;
    if (y1 > y0)
      stoss += angle, ++rises;
    else
      lee += angle, ++falls, height += y0 - y1;
    if (k >= 2 && y1 > y0) spacing += (x1 - ext[k - 2].first) * dx, ++s.crests;  // crest to crest
  }
  s.wavelength = s.crests ? spacing / s.crests : 0;
  s.height = falls ? height / falls : 0;
  s.ripple_index = s.height > 0 ? s.wavelength / s.height : 0;
  s.stoss_deg = rises ? stoss / rises : 0;
  s.lee_deg = falls ? lee / falls : 0;
  return s;
}

double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const auto n = static_cast<double>(x.size());
  if (x.size() < 3) return std::nan("");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
  const double den = n * sxx - sx * sx;
  return den > 0 ? (n * sxy - sx * sy) / den : std::nan("");
}

}  // namespace grainlab::ripples
