#pragma once
// The 3-D hybrid model's ripple runs (Huo et al. 2021, section 3.2): the transport of transport.hpp over
// an erodible height-field bed, started flat with a few trigger grains, with the bed statistics of
// bed_statistics.hpp taken at every frame. The caller drives it frame by frame (the CLI streams frames to
// HDF5 and shows progress).
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bed_statistics.hpp"
#include "height_field.hpp"
#include "transport.hpp"

namespace grainlab::ripples::hybrid {

struct RippleOptions : TransportOptions {
  RippleOptions();       // the paper's ripple case: 4000 d x 200 d, s = 2098, Ga = 38
  double cell = 2;       // key-point spacing, d
  double packing = 0.6;  // phi_b
  double repose_deg = 30;
  double erodible = 80;           // depth of sand, d
  bool bilinear = false;          // grains settle / leave shared among four key points (HeightFieldParams)
  double initial_amplitude = 0;   // d: the bed starts as a downwind sine of this amplitude (0: flat)
  double initial_wavelength = 0;  // d, rounded to fit the length a whole number of times
  double affectable_depth = 2;    // psi0 of the surface layer on a bed of several sizes, d (unstated)
  double duration = 100000;       // t*
  double frame_every = 1000;      // t* between bed frames
  double sample_every = 10;       // t* between flux samples
};
void check_ripple_options(const RippleOptions& o);  // throws std::invalid_argument
// Why the key-point spacing cannot carry the largest grain size (empty when it can).
std::string cell_too_small(const RippleOptions& o);
// The steepest step between neighbouring key points, in degrees, on which a settling grain of the largest
// size stays where it fell: repose less the grain's own rise over a cell. The repose rule keeps every step
// within repose once the grain has settled, so on fine cells it holds the bed's grain-scale slopes well
// below repose (17.7 deg at cell 1.5 d, 25.1 at 2 d, 29.4 at 4 d), and that sets the ripples' flanks
// (docs/hybrid.md, "The key points' own repose angle").
double key_point_repose_deg(const RippleOptions& o);
// The frames' times in t*: 0, every, 2 every, ... up to the duration, and the duration itself when it is
// not a whole number of intervals (the last one is then shorter), so that a run always reaches it.
std::vector<double> frame_times(double duration, double every);

// One bed frame: heights in grain diameters relative to the initial surface, x fastest.
struct BedFrame {
  double t_star = 0;
  std::vector<double> h;
  std::vector<double> profile;  // h averaged across the bed (over y), one value per key-point column
  double dx = 0;                // key-point spacing, d
  BedStatistics stats;          // grain diameters
  double shift = 0;             // downwind shift since the previous frame, d
  double mass_flux_star = 0;    // Q* averaged since the previous frame
  double airborne = 0;          // grains in flight, averaged since the previous frame
  double u_star_bed = 0;        // cm/s
  double loosening = 1;         // E_eff / E_d2
  // The roughness z0 (d) of the wind's log layer far above the grains (heights frame_log_band), the wind
  // averaged over the flux samples since the previous frame: eq. 32's z0, whose values at several u*
  // give the focal point as the ripples grow (Fig. 15). NaN at the first frame (no samples yet).
  double z0 = std::nan("");
  // A bed of several sizes: the surface layer's mean grain size (d) by key-point column, averaged across
  // the bed, and over the highest and the lowest quarter of those columns by the profile's height, both
  // smoothed over a quarter wavelength (coarse crests: crest > trough). Empty / NaN on a bed of one size.
  std::vector<double> size_profile;
  double size_crest = std::nan(""), size_trough = std::nan("");
  // Mid-air collisions per t* per 1,000 d^2 of bed since the previous frame (NaN at the first): they set
  // how high the ripples grow for their length (docs/hybrid.md, "Mid-air collisions set the ripples'
  // aspect").
  double collision_rate = std::nan("");
};

class RippleRun {
 public:
  explicit RippleRun(const RippleOptions& o);
  // Runs until t* reaches `t_star` (or transport dies: no grain airborne); calls progress(t*) at every
  // flux sample.
  void advance_to(double t_star, const std::function<void(double)>& progress = nullptr);
  double t_star() const { return transport_->time() / transport_->time_unit(); }
  // The bed now, with the averages since the previous call (the first call: since the start).
  BedFrame frame();
  const HeightField& bed() const { return bed_; }
  const Transport& transport() const { return *transport_; }
  // Every impact from now on is appended to `log` (null: none are).
  void log_impacts(std::vector<ImpactRecord>* log) { transport_->impact_log = log; }
  // Flux samples since the start: t*, Q*, grains airborne.
  const std::vector<std::array<double, 3>>& series() const { return series_; }
  const RippleOptions& options() const { return o_; }
  // The run's whole state as named tables under `prefix`, and back (throws std::invalid_argument).
  std::vector<SampleTable> save(const std::string& prefix) const;
  void restore(const std::map<std::string, SampleTable>& tables, const std::string& prefix);

 private:
  void surface_sizes(const SurfaceLayer& layer, BedFrame& f) const;
  RippleOptions o_;
  HeightField bed_;
  std::unique_ptr<Transport> transport_;
  std::vector<std::array<double, 3>> series_;
  std::vector<double> last_h_;
  double next_sample_ = 0, q_sum_ = 0, air_sum_ = 0, samples_ = 0;
  // The wind at the column's nodes summed over the samples since the previous frame. Not in save():
  // checkpoints are taken at frames, where it is zero.
  std::vector<double> wind_sum_;
  // The collisions counted and t* at the previous frame (a restored run: at its checkpoint, a frame).
  std::uint64_t frame_collisions_ = 0;
  double frame_t_star_ = 0;
};

// The impacts of `log` from t* = `from` on as a table "impacts": t*, where (d, x downwind), the velocity
// (cm/s), the bed triangle's normal, the size class, and the speed (cm/s) and descent angle below the
// horizontal (deg) that the analysis reads (tools/impact_slopes.py).
SampleTable impact_table(const std::vector<ImpactRecord>& log, double from, double time_unit,
                         double diameter);

// The heights (d) at which a ripple run fits its frames' log layer: 300-1000 d, or within a shorter
// column, its upper part (a quarter to 0.85 of its height).
std::array<double, 2> frame_log_band(double column_height);

}  // namespace grainlab::ripples::hybrid

namespace grainlab::ripples::hybrid {

// What a ripple run's frames show: the exponential growth rate of A over the first half of the frames
// (1/t*), the coarsening exponent chi of lambda ~ t^chi over the second half, the migration speed (d per
// t*, downwind positive) over the second half, from the frames' profiles with their time mean removed
// (profile_migration). NaN where the frames do not allow a fit (no wavelength).
struct RippleTrends {
  double growth_rate = 0, chi = 0, migration_speed = 0;
  // The linear response by wavelength band (d, per t*, d per t*) over the frames after the flat start
  // that are equally spaced: a positive growth rate marks the band in which ripples emerge.
  std::vector<BandResponse> response;
  // The mean RI over the frames in the paper's window, t* = 5e4-3e5 (its Fig. 9 inset averages RI over
  // that window, one value per wind speed), and how many frames it averages (those with a wavelength);
  // NaN and 0 without any.
  static constexpr double kWindowStart = 5e4, kWindowEnd = 3e5;
  double window_ripple_index = std::nan("");
  std::size_t window_frames = 0;
  // The same mean of the crests' ripple index (BedStatistics::crest_ripple_index), over the window's frames
  // that have one (older checkpoints' frames and crestless beds do not).
  double window_crest_ripple_index = std::nan("");
};
RippleTrends ripple_trends(const std::vector<BedFrame>& frames);
// A trend's number for people: three significant digits, or "n/a" where the frames did not allow the fit
// (NaN: a run too short for ripples, a window with no frames).
std::string shown_fit(double value);

}  // namespace grainlab::ripples::hybrid
