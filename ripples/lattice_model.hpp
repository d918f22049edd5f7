#pragma once
// The thesis's lattice-bed model (Ch. V section 4, Fig. 5.21). Circular grains of diameter d sit on a
// regular lattice, each in the pocket between two grains below; the lattice is stretched so neighbouring
// surface grains lie at the 30 deg angle of repose (horizontal grain spacing sqrt(3) d, layer spacing d/2).
// The surface is therefore a walk of +-1 layer per half-spacing "column": h_{i+1} - h_i = +-1 everywhere.
// Grains fired at a fixed angle from random points hit the first surface grain their path meets; the hit
// grain (target ejection) or a brink grain found near it (brink ejection) hops a fixed number of lattice
// spacings forward (upstream-side hit) or backward (downstream-side hit), drops, and rolls on in its
// direction to the first pocket. A grain whose support is taken away rolls down to the next pocket.
#include <complex>
#include <cstdint>
#include <string>
#include <vector>

#include "rng.hpp"

namespace grainlab::ripples {

struct LatticeParams {
  int columns = 2000;              // half-spacing columns, periodic (even); a lattice spacing is 2 columns
  double impact_deg = 15;          // path angle below the horizontal (not given in the thesis; 10-15 natural)
  int forward = 15;                // hop of a grain hit on its upstream side, lattice spacings
  int backward = 5;                // hop of a grain hit on its downstream side, lattice spacings
  double brink_probability = 0.5;  // share of impacts that eject a brink grain instead of the target
  int brink_lookahead = 10;        // how far a brink is looked for, lattice spacings
  int hits_per_point = 1;          // impacts fired from each random point (the thesis's Fig. 5.23c: 2)
  // Splash mode: each ejected grain hops a length drawn from these (grain diameters, negative: upstream),
  // e.g. the measured ejecta of a grainlab-splash/1 file; empty: the fixed forward / backward hops.
  std::vector<double> hops_d;
  int depth = 40;  // the flat start's layer index (a datum: the bed has no floor, troughs may go below 0)
  // Where a hopping grain settles if it does not land in a pocket: onward in its direction to the next
  // pocket (the thesis's words, the default), or downhill to the nearest one (as a grain rolls).
  bool land_downhill = false;
  double roughness = 0;  // initial surface: share of columns given a random +-1 bump (0: flat)
  // A seeded start instead of the flat one: a downstream sine of this amplitude (layers) and wavelength
  // (lattice spacings, rounded so that a whole number of waves fits), drawn as the lattice walk nearest
  // it. Its growth or decay measures the model's linear response (lattice_linear_rate).
  double initial_amplitude = 0;
  double initial_wavelength = 0;
  std::uint64_t seed = 1;
};

class LatticeModel {
 public:
  explicit LatticeModel(const LatticeParams& p);
  // Fires `impacts` grains.
  void fire(long impacts);
  // Surface layer index per column (a grain's centre sits at h d / 2 above the datum).
  const std::vector<int>& heights() const { return h_; }
  long impacts() const { return impacts_; }
  // Impacts per surface grain (there is one surface grain per lattice spacing, i.e. per 2 columns).
  double ejections_per_surface_grain() const { return 2.0 * impacts_ / p_.columns; }
  long grains() const;  // sum of (h - base) / 2: conserved
  long forward_hops() const { return forward_; }
  long backward_hops() const { return backward_; }

 private:
  void seed_sine(int base);
  int hit_column(double start_x, double& side_offset);
  void eject(int column, int direction, int hop_columns);
  void drop(int column, int direction);
  void land_onward(int column, int direction);
  void land_at(int column);
  int first_pocket(int column, int direction) const;
  // Slope bits (is the next column higher?) with kPad columns of wrapped margin on each side, so that
  // pockets and brinks are found a word at a time.
  static constexpr int kPad = 128;
  bool rises(int column) const;
  std::uint64_t rise_bits(int column) const;
  void put_rise(int column, bool up);
  void write_bit(int b, bool up) {  // slope bit at position b of rise_
    std::uint64_t& w = rise_[static_cast<std::size_t>(b >> 6)];
    const std::uint64_t bit = std::uint64_t{1} << (b & 63);
    w = (w & ~bit) | (up ? bit : 0);
  }
  std::vector<std::uint64_t> rise_;
  void set(int i, int v);
  void remove_top(int i);
  int near(int i) const;  // wrap for |offsets| below the domain length
  int find_brink(int from, int direction, int limit) const;
  LatticeParams p_;
  std::vector<int> h_;
  std::vector<int> unstable_;  // remove_top's work list, kept to avoid allocating per impact
  // g_i = h_i d / 2 + step i: the hit search's one number per column (see hit_column), and its largest
  // value in each block of columns.
  double ray_invariant(int i, int h) const { return h * 0.5 + step_ * i; }
  std::vector<double> g_, block_g_;
  double step_ = 0;  // the path's drop per column, d
  int max_h_ = 0;    // at least the highest column's height (exact every 4096 impacts)
  long next_recount_ = 0;
  Rng rng_;
  long impacts_ = 0, forward_ = 0, backward_ = 0;
  double tan_a_, cos_a_;
};

// The waves a seeded start fits into the domain (at least 1), and the complex amplitude (layers) of that
// Fourier mode of a surface: h = Re(a exp(2 pi i waves x / length)) + the rest.
int lattice_seeded_waves(const LatticeParams& p);
std::complex<double> lattice_mode(const std::vector<int>& h, int waves);

// Linear theory of target ejection on a gentle surface (Anderson's argument, on the lattice). A path at
// angle a meets a stretch of bed in proportion to its horizontal length plus its rise over tan a, so the
// impact rate per lattice spacing is 1 + h' / (2 sqrt(3) tan a), h' in layers per spacing (a layer is
// d / 2, a spacing sqrt(3) d). Each impact takes one grain (one layer of the spacing's mean height) from
// where it hits to a hop L_f downstream, or, for the share b hit on their downstream side, L_b upstream:
//   dh/dtau = -I(x) + (1 - b) I(x - L_f) + b I(x + L_b),
// tau in impacts per surface grain. A mode exp(i k x) grows at Re s = c k [(1 - b) sin k L_f - b sin k L_b]
// and moves downstream at -Im s / k = c [1 - (1 - b) cos k L_f - b cos k L_b], c = 1 / (2 sqrt(3) tan a).
// Wavelength and hops in lattice spacings; s per ejection per surface grain.
std::complex<double> lattice_linear_rate(double impact_deg, double forward, double backward,
                                         double backward_share, double wavelength);

// The measured linear response of a seeded start: `seeds` runs (seeds p.seed, p.seed + 1, ...) of p, each
// with `frames` looks over `tau` impacts per surface grain. The seeded mode's complex amplitude, averaged
// over the runs (the shot noise averages out of it), is fitted with a exp(s tau) by least squares on
// ln |a| (growth) and on its unwrapped phase (speed). The share of hits on the downstream side is counted,
// and the theory above evaluated with it.
struct LatticeResponse {
  double wavelength = 0;         // lattice spacings, as fitted to the domain
  double growth = 0, speed = 0;  // per ejection per surface grain; lattice spacings per ejection per grain
  double theory_growth = 0, theory_speed = 0;
  double backward_share = 0;
  double amplitude_start = 0, amplitude_end = 0;  // |a|, layers
};
LatticeResponse lattice_linear_response(LatticeParams p, double tau, int frames, int seeds);

// The surface in grain diameters, one value per lattice spacing (sqrt(3) d apart): the mean of its two
// columns' layer indices (a layer is d / 2), which removes the lattice's zig-zag.
template <typename T>
std::vector<double> lattice_profile(const std::vector<T>& layers) {
  std::vector<double> y;
  for (std::size_t i = 0; i + 1 < layers.size(); i += 2) y.push_back(0.25 * (layers[i] + layers[i + 1]));
  return y;
}

// Surface statistics in lattice units (x in columns, heights in layers; the slopes in degrees use the
// lattice geometry: a column is sqrt(3) d / 2 wide, a layer d / 2 high).
struct LatticeSurfaceStats {
  double wavelength = 0;              // mean crest spacing of the smoothed surface, lattice spacings
  double height = 0;                  // mean crest-to-next-trough height, layers (d / 2)
  double stoss_deg = 0, lee_deg = 0;  // mean slopes of the rising and falling flanks of the smoothed surface
  int crests = 0;
  double rms = 0;  // layers
};
// f(lambda) (eq. 5.2) of the surface sampled once per lattice spacing (heights in layers, sigma 2 layers),
// lags up to a quarter of the domain; its peak and the autocorrelation wavelength, in lattice spacings.
struct LatticeLengthScales {
  std::vector<double> f;  // f[l - 1]: lag l lattice spacings
  int f_peak = 0;
  double autocorrelation_wavelength = 0;
};
LatticeLengthScales lattice_length_scales(const std::vector<int>& h);

// `smooth_columns`: the smoothing half-width (a running mean) that removes the lattice's zig-zag.
LatticeSurfaceStats lattice_surface_stats(const std::vector<int>& h, int smooth_columns = 8);

}  // namespace grainlab::ripples
