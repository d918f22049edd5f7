#pragma once
// Analysis of any 1-D surface h(x) on a uniform, periodic grid (thesis Ch. V section 5): the Tombrello
// smoothing of eq. 5.1, the length-scale distribution f(lambda) of eq. 5.2 (the spec's intended form), the
// power spectrum, and the wavelength by autocorrelation.
#include <vector>

namespace grainlab::ripples {

// Eq. 5.1: y_s(i) = sum_{j=i-n}^{i+n} y(j) w_ij / sum w_ij with w_ij = exp(-(y(i) - y(j))^2 / 2 sigma^2):
// neighbours at very different heights (a slipface) weigh little, so edges survive the smoothing.
std::vector<double> tombrello_smooth(const std::vector<double>& y, int n, double sigma);

// Eq. 5.2: f(l) proportional to sum_j exp(-(h_j - h_{j+l})^2 / 2 sigma^2) for lags l = 1..max_lag
// (periodic, so every lag has N pairs), normalised to sum 1. f[0] is lag 1.
std::vector<double> length_scale_distribution(const std::vector<double>& h, int max_lag, double sigma);
// The lag (1-based) of f's largest value beyond its first local minimum: the preferred length scale.
// 0 if f never turns up.
int length_scale_peak(const std::vector<double>& f);

// |DFT|^2 of h - mean at wavenumbers 1..N/2 (index k - 1: wavelength N / k grid steps).
std::vector<double> power_spectrum(const std::vector<double>& h);
// The lag of the autocorrelation's first maximum after its first zero crossing that reaches half its
// highest maximum (grid steps); 0 if none.
double autocorrelation_wavelength(const std::vector<double>& h);

// The rms of y about its mean (0 for fewer than one point).
double rms_height(const std::vector<double>& y);

// Least-squares slope of y against x; NaN with fewer than 3 points or no spread in x.
double least_squares_slope(const std::vector<double>& x, const std::vector<double>& y);

// Ripple shape of a periodic surface (x spacing dx, heights in the same unit; wind towards +x): crests and
// troughs alternate, each standing at least `min_relief` above / below its neighbours (smaller wiggles are
// skipped). Wavelength: mean crest spacing; height: mean crest-to-next-trough drop; ripple index: their
// ratio; stoss / lee: mean angles of the rising / falling flanks from trough to crest and back.
struct SurfaceShape {
  double wavelength = 0, height = 0, ripple_index = 0, stoss_deg = 0, lee_deg = 0, rms = 0;
  int crests = 0;
};
SurfaceShape surface_shape(const std::vector<double>& h, double dx, double min_relief);

}  // namespace grainlab::ripples
