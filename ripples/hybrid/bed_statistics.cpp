#include "bed_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <unsupported/Eigen/FFT>

#include "surface_analysis.hpp"

namespace grainlab::ripples::hybrid {

namespace {

using Spectrum = std::vector<std::complex<double>>;

// Each slice's spectrum, its mean removed.
std::vector<Spectrum> slice_spectra(const std::vector<double>& h, std::size_t nx, std::size_t ny) {
  Eigen::FFT<double> fft;
  std::vector<Spectrum> out(ny);
  std::vector<double> row(nx);
  for (std::size_t j = 0; j < ny; ++j) {
    double mean = 0;
    for (std::size_t i = 0; i < nx; ++i) mean += h[j * nx + i];
    mean /= static_cast<double>(nx);
    for (std::size_t i = 0; i < nx; ++i) row[i] = h[j * nx + i] - mean;
    fft.fwd(out[j], row);
  }
  return out;
}

// The slice-averaged circular cross-correlation of a and b: sum_x a(x) b(x + dl) / nx.
std::vector<double> correlate(const std::vector<Spectrum>& a, const std::vector<Spectrum>& b,
                              std::size_t nx) {
  Eigen::FFT<double> fft;
  Spectrum sum(a[0].size(), 0.0);
  for (std::size_t j = 0; j < a.size(); ++j)
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += std::conj(a[j][k]) * b[j][k];
  std::vector<double> c(nx);
  fft.inv(c, sum);
  const double scale = 1 / (static_cast<double>(nx) * static_cast<double>(a.size()));
  for (double& v : c) v *= scale;
  return c;
}

// The shift (in d) within +- max_shift at which the periodic cross-correlation c peaks, refined between
// grid points by the parabola through the peak and its two neighbours: a ripple moves a fraction of a
// key-point spacing between frames, and whole spacings alone would read every frame's shift as 0 or dx.
double correlation_peak_shift(const std::vector<double>& c, double dx, double max_shift) {
  const auto nx = static_cast<long>(c.size());
  const auto reach = std::min<long>(static_cast<long>(max_shift / dx), nx / 2 - 1);
  auto at = [&](long s) { return c[static_cast<std::size_t>(s < 0 ? s + nx : s)]; };
  long best = 0;
  for (long s = -reach; s <= reach; ++s)
    if (at(s) > at(best)) best = s;
  const double a = at(best - 1), b = at(best), e = at(best + 1), den = a - 2 * b + e;
  const double off = den < 0 ? std::clamp(0.5 * (a - e) / den, -0.5, 0.5) : 0.0;
  return (static_cast<double>(best) + off) * dx;
}

// The flank angles and crest measures of BedStatistics. Slice by slice, not on the across-averaged profile:
// crests that are not straight across the bed (Y-junctions, defects) would be smeared flat by the average.
void slice_shapes(const std::vector<double>& h, std::size_t nx, std::size_t ny, double dx, BedStatistics& r) {
  double stoss = 0, lee = 0, spacing = 0, height = 0;
  int slices = 0;
  for (std::size_t j = 0; j < ny; ++j) {
    const std::vector<double> row(h.begin() + static_cast<long>(j * nx),
                                  h.begin() + static_cast<long>((j + 1) * nx));
    // Half the rms height, as `ripples analyze` takes by default, but at least a grain: on a bed without
    // ripples half the rms is the grain-scale roughness, whose bumps a key point apart read as 14 deg flanks.
    const SurfaceShape s = surface_shape(row, dx, std::max(0.5 * rms_height(row), 1.0));
    if (s.crests == 0) continue;
    stoss += s.stoss_deg, lee += s.lee_deg, ++slices;
    spacing += s.wavelength, height += s.height;
  }
  if (slices == 0) return;
  r.stoss_deg = stoss / slices, r.lee_deg = lee / slices;
  r.crest_spacing = spacing / slices, r.crest_height = height / slices;
  if (r.crest_height > 0) r.crest_ripple_index = r.crest_spacing / r.crest_height;
}

}  // namespace

std::vector<double> slice_autocorrelation(const std::vector<double>& h, std::size_t nx, std::size_t ny) {
  const std::vector<Spectrum> s = slice_spectra(h, nx, ny);
  return correlate(s, s, nx);
}

BedStatistics bed_statistics(const std::vector<double>& h, std::size_t nx, std::size_t ny, double dx) {
  BedStatistics r;
  for (double v : h) r.mean += v;
  r.mean /= static_cast<double>(h.size());
  const std::vector<double> c = slice_autocorrelation(h, nx, ny);
  r.amplitude = 2 * std::sqrt(2 * std::max(0.0, c[0]));
  // The first peak beyond the first trough: from the first negative lag, the largest C up to where it
  // turns negative again (the first positive lobe after the first negative one).
  const std::size_t half = nx / 2;
  std::size_t k = 1;
  while (k < half && c[k] > 0) ++k;
  while (k < half && c[k] <= 0) ++k;
  std::size_t best = 0;
  for (; k < half && c[k] > 0; ++k)
    if (best == 0 || c[k] > c[best]) best = k;
  if (best > 0) {
    // A parabola through the peak and its neighbours puts it between grid points.
    const double a = c[best - 1], b = c[best], e = c[best + 1], den = a - 2 * b + e;
    const double off = den < 0 ? std::clamp(0.5 * (a - e) / den, -0.5, 0.5) : 0.0;
    r.wavelength = (static_cast<double>(best) + off) * dx;
    if (r.amplitude > 0) r.ripple_index = r.wavelength / r.amplitude;
  }
  slice_shapes(h, nx, ny, dx, r);
  return r;
}

double bed_shift(const std::vector<double>& before, const std::vector<double>& after, std::size_t nx,
                 std::size_t ny, double dx, double max_shift) {
  return correlation_peak_shift(correlate(slice_spectra(before, nx, ny), slice_spectra(after, nx, ny), nx),
                                dx, max_shift);
}

double profile_migration(const std::vector<std::vector<double>>& profiles, double dx, double max_shift) {
  if (profiles.size() < 2) return 0;
  const std::size_t nx = profiles[0].size();
  std::vector<double> mean(nx, 0.0);
  for (const auto& p : profiles)
    for (std::size_t i = 0; i < nx; ++i) mean[i] += p[i] / static_cast<double>(profiles.size());
  std::vector<Spectrum> spectra;
  for (const auto& p : profiles) {
    std::vector<double> moving(nx);
    for (std::size_t i = 0; i < nx; ++i) moving[i] = p[i] - mean[i];
    spectra.push_back(slice_spectra(moving, nx, 1)[0]);
  }
  std::vector<double> c(nx, 0.0);
  for (std::size_t k = 1; k < spectra.size(); ++k) {
    const std::vector<double> one = correlate({spectra[k - 1]}, {spectra[k]}, nx);
    for (std::size_t i = 0; i < nx; ++i) c[i] += one[i];
  }
  return correlation_peak_shift(c, dx, max_shift);
}

std::vector<BandResponse> band_response(const std::vector<std::vector<double>>& profiles, double dx,
                                        double dt) {
  std::vector<BandResponse> out;
  if (profiles.size() < 3 || profiles[0].size() < 4) return out;
  const std::size_t n = profiles[0].size();
  std::vector<Spectrum> spectra;
  for (const auto& p : profiles) spectra.push_back(slice_spectra(p, n, 1)[0]);
  for (std::size_t lo = 1; lo <= n / 2; lo *= 2) {
    const std::size_t hi = std::min(2 * lo, n / 2 + 1);  // modes [lo, hi)
    std::complex<double> cross = 0;
    double power = 0, k_mean = 0;  // k weighted by each mode's power: the band's phase speed is its modes'
    for (std::size_t m = lo; m < hi; ++m) {
      const double k = 2 * M_PI * static_cast<double>(m) / (static_cast<double>(n) * dx);
      for (std::size_t t = 0; t + 1 < spectra.size(); ++t) {
        cross += std::conj(spectra[t][m]) * spectra[t + 1][m];
        power += std::norm(spectra[t][m]), k_mean += k * std::norm(spectra[t][m]);
      }
    }
    if (!(power > 0)) continue;
    k_mean /= power;
    const std::complex<double> rho = cross / power, s = std::log(rho) / dt;
    // The fit's standard error: the residuals' variance over the power, split between the real and
    // imaginary parts, carried through the logarithm.
    double residual = 0;
    std::size_t samples = 0;
    for (std::size_t m = lo; m < hi; ++m)
      for (std::size_t t = 0; t + 1 < spectra.size(); ++t, ++samples)
        residual += std::norm(spectra[t + 1][m] - rho * spectra[t][m]);
    const double se = samples > 1 ? std::sqrt(residual / static_cast<double>(samples - 1) / (2 * power)) /
                                        (std::abs(rho) * dt)
                                  : std::nan("");
    const double length = static_cast<double>(n) * dx;
    out.push_back({length / static_cast<double>(hi - 1), length / static_cast<double>(lo), s.real(),
                   -s.imag() / k_mean, se});
  }
  return out;
}

}  // namespace grainlab::ripples::hybrid
