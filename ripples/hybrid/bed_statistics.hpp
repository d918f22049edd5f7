#pragma once
// Ripple diagnostics of a height field (Huo et al. 2021, section 3.2): the bed cut into streamwise slices,
// each slice's autocorrelation C(dl) = <h(x) h(x + dl)> - <h>^2, averaged over slices. The amplitude is
// A = 2 sqrt(2 C(0)) (for a sine, its crest-to-trough height), the wavelength the first peak of C at
// dl > 0, the ripple index lambda / A. The migration between two bed frames is the shift that best lines
// the slices up (the peak of their cross-correlation).
#include <cstddef>
#include <vector>

namespace grainlab::ripples::hybrid {

struct BedStatistics {
  double amplitude = 0;     // A, same unit as h
  double wavelength = 0;    // same unit as dx; 0 when C has no peak beyond its first trough
  double ripple_index = 0;  // lambda / A (0 without a wavelength)
  double mean = 0;
  // The ripples' flanks, slice by slice (surface_shape of surface_analysis.hpp, crests and troughs standing
  // out by half the slice's rms height and by at least one grain diameter, h's unit), averaged over the
  // slices that have crests: the mean angle (deg) of the rising flank from trough to crest going downwind
  // (stoss) and of the falling one (lee). Field ripples are asymmetric, with a lee steeper than the stoss
  // (thesis Table 5.1); 0 on a bed with none.
  double stoss_deg = 0, lee_deg = 0;
  // The crests' own wavelength and height from the same slices: the mean crest-to-crest spacing and
  // crest-to-next-trough drop (h's and dx's units), and their ratio. A cross-check on the autocorrelation,
  // whose first peak fades when the crests are unevenly spaced and then jumps to the next (docs/hybrid.md,
  // "Two measures of the wavelength"); 0 on a bed with none.
  double crest_spacing = 0, crest_height = 0, crest_ripple_index = 0;
};

// h: nx * ny heights, x fastest, spacing dx, periodic in x. Wind towards +x.
BedStatistics bed_statistics(const std::vector<double>& h, std::size_t nx, std::size_t ny, double dx);
// The slice-averaged autocorrelation C(dl) at lags 0..nx-1 (periodic).
std::vector<double> slice_autocorrelation(const std::vector<double>& h, std::size_t nx, std::size_t ny);
// The downwind shift (same unit as dx) that carries `before` onto `after`, searched within +-max_shift and
// refined between grid points by a parabola through the correlation's peak.
double bed_shift(const std::vector<double>& before, const std::vector<double>& after, std::size_t nx,
                 std::size_t ny, double dx, double max_shift);

// The downwind shift per frame of bedforms in a series of slice-averaged profiles (one per frame, equally
// spaced in time): each position's mean over the series is removed first, so roughness that stays put
// (grain-scale noise no grain has touched) does not pin the answer to zero; then the cross-correlations
// of consecutive profiles are summed and their peak within +-max_shift taken (refined by a parabola).
double profile_migration(const std::vector<std::vector<double>>& profiles, double dx, double max_shift);

// The bed's linear response, band by band: a series of slice-averaged profiles (equally spaced by dt) is
// fitted, Fourier mode by mode, with h_k(t + dt) = exp(s dt) h_k(t) (least squares over consecutive frames,
// pooled over the modes of a band). Re s is the growth rate (negative: the band is damped; shot noise that
// the bed forgets gives a negative rate, a linearly unstable bed a positive one), -Im s / k the downwind
// phase speed. Bands are octaves of wavelength from the domain length down to two spacings.
struct BandResponse {
  double lambda_min = 0, lambda_max = 0;  // same unit as dx
  double growth_rate = 0;                 // per unit of dt
  double phase_speed = 0;                 // dx units per unit of dt, downwind positive
  double growth_error = 0;                // the growth rate's standard error (from the fit's residuals)
};
std::vector<BandResponse> band_response(const std::vector<std::vector<double>>& profiles, double dx,
                                        double dt);

}  // namespace grainlab::ripples::hybrid
