#include "ripple_run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "focal_point.hpp"
#include "surface_analysis.hpp"

namespace grainlab::ripples::hybrid {

RippleOptions::RippleOptions() {
  // s = 2098 and Ga = 38 (section 3.2): quartz-like grains of 0.0251 cm in air of 0.00126 g/cm^3.
  grain_density = 2.65, fluid_density = 2.65 / 2098, diameter = 0.0251, viscosity = 0.146;
  length = 4000, width = 200, height = 1200, triggers = 200, u_star = 30;
  wind_loosened = true;
  // Over an erodible bed the wind column stands on the bed beneath each grain: with the column on the mean
  // level, crests reach into faster wind than troughs and every wavelength decays (docs/hybrid.md).
  wind_follows_bed = true;
}

namespace {
double largest_grain(const RippleOptions& o) {
  return o.sizes.empty() ? 1.0 : *std::max_element(o.sizes.begin(), o.sizes.end());
}
// How far one grain of s diameters raises its key point, in diameters.
double grain_rise(const RippleOptions& o, double s) {
  return M_PI / 6 * s * s * s / (o.packing * o.cell * o.cell);
}
// The steepest step repose allows between neighbouring key points, in diameters.
double repose_step(const RippleOptions& o) {
  return std::tan(o.repose_deg * M_PI / 180) * o.cell;
}
}  // namespace

double key_point_repose_deg(const RippleOptions& o) {
  return std::atan((repose_step(o) - grain_rise(o, largest_grain(o))) / o.cell) * 180 / M_PI;
}

std::string cell_too_small(const RippleOptions& o) {
  // One grain of the largest size must not raise its key point by more than repose allows over a cell:
  // nothing would then smooth the spike it leaves, and every grain that settles would roll on to the
  // lowest point around it (on a bed of one size, cell < 1.16 d at repose 30 deg).
  const double s = largest_grain(o), rise = grain_rise(o, s), allowed = repose_step(o);
  if (rise < allowed) return "";
  return fmt::format(
      "cell {} d is too small for grains of {} d: one raises its key point {:.2f} d, more than repose allows "
      "over a cell ({:.2f} d); use cell >= {:.2f} d",
      o.cell, s, rise, allowed,
      1.01 * s * std::cbrt(M_PI / (6 * o.packing * std::tan(o.repose_deg * M_PI / 180))));
}

std::vector<double> frame_times(double duration, double every) {
  const auto whole = static_cast<std::size_t>(std::floor(duration / every + 1e-9));
  std::vector<double> t;
  for (std::size_t k = 0; k <= whole; ++k) t.push_back(static_cast<double>(k) * every);
  // (A remainder under a millionth of an interval is the division's rounding, not a shorter interval.)
  if (duration - t.back() > 1e-6 * every) t.push_back(duration);
  return t;
}

void check_ripple_options(const RippleOptions& o) {
  check_transport_options(o);
  for (double v : {o.cell, o.packing, o.duration, o.frame_every, o.sample_every, o.affectable_depth})
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument(
          "cell, packing, duration, frame_every, sample_every and affectable_depth must be positive");
  if (o.length < 3 * o.cell || o.width < 3 * o.cell)
    throw std::invalid_argument("the bed needs at least 3 cells each way");
  if (const std::string why = cell_too_small(o); !why.empty()) throw std::invalid_argument(why);
  if (o.initial_amplitude < 0 || o.initial_amplitude >= o.erodible ||
      (o.initial_amplitude > 0 && !(o.initial_wavelength >= 2 * o.cell && o.initial_wavelength <= o.length)))
    throw std::invalid_argument(
        "an initial sine needs amplitude in [0, erodible) and a wavelength of 2 cells to the bed's length");
}

namespace {
HeightFieldParams bed_params(const RippleOptions& o) {
  check_ripple_options(o);
  const double d = o.diameter;
  return {o.length * d, o.width * d, o.cell * d, d, o.packing, o.repose_deg, o.erodible * d, o.bilinear};
}
}  // namespace

namespace {
// The bed at the start: flat, or a downwind sine of the configured amplitude whose wavelength is the
// nearest that fits the periodic length (a seeded perturbation: whether it grows or decays measures the
// model's linear stability directly, above the shot noise).
HeightField initial_bed(const RippleOptions& o) {
  HeightField bed(bed_params(o));
  if (!o.sizes.empty()) bed.set_mixture(o.sizes, o.fractions, o.affectable_depth * o.diameter);
  if (o.initial_amplitude > 0) {
    const double waves = std::max(1.0, std::round(o.length / o.initial_wavelength));
    auto& h = bed.heights();
    for (std::size_t j = 0; j < bed.ny(); ++j)
      for (std::size_t i = 0; i < bed.nx(); ++i)
        h[j * bed.nx() + i] =
            o.initial_amplitude * o.diameter *
            std::sin(2 * M_PI * waves * static_cast<double>(i) / static_cast<double>(bed.nx()));
    bed.refresh();
  }
  return bed;
}
}  // namespace

RippleRun::RippleRun(const RippleOptions& o)
    : o_(o), bed_(initial_bed(o)), transport_(std::make_unique<Transport>(o, &bed_)) {
  last_h_ = bed_.heights();
}

void RippleRun::advance_to(double t_star, const std::function<void(double)>& progress) {
  Transport& t = *transport_;
  const double unit = t.time_unit();
  while (t.time() < t_star * unit && t.airborne() > 0) {
    t.step();
    if (t.time() < next_sample_ * unit) continue;
    const double q = t.mass_flux() / t.flux_unit(), air = static_cast<double>(t.airborne());
    series_.push_back({t.time() / unit, q, air});
    q_sum_ += q, air_sum_ += air, samples_ += 1;
    const std::vector<double>& u = t.wind().u();
    wind_sum_.resize(u.size(), 0.0);
    for (std::size_t k = 0; k < u.size(); ++k) wind_sum_[k] += u[k];
    next_sample_ += o_.sample_every;
    if (progress) progress(t.time() / unit);
  }
}

SampleTable impact_table(const std::vector<ImpactRecord>& log, double from, double time_unit,
                         double diameter) {
  SampleTable t{
      "impacts",
      fmt::format("every impact on the bed from t* = {:g}: t*,", from) +
          " x and y (d, x downwind) where it met the bed, its velocity (cm/s), the normal of the "
          "bed triangle it met, its size class, its speed (cm/s) and its descent below the "
          "horizontal (deg)",
      {"t_star", "x", "y", "vx", "vy", "vz", "nx", "ny", "nz", "size_class", "speed", "descent_deg"},
      {}};
  for (const ImpactRecord& r : log) {
    const double t_star = r.t / time_unit;
    if (t_star < from) continue;
    const double speed = std::sqrt(r.vx * r.vx + r.vy * r.vy + r.vz * r.vz);
    const double descent = std::atan2(-r.vz, std::hypot(r.vx, r.vy)) * 180 / M_PI;
    t.rows.push_back({t_star, r.x / diameter, r.y / diameter, r.vx, r.vy, r.vz, r.nx, r.ny, r.nz,
                      static_cast<double>(r.kind), speed, descent});
  }
  return t;
}

namespace {
// A periodic running mean over 2 m + 1 values.
std::vector<double> running_mean(const std::vector<double>& v, std::size_t m) {
  const std::size_t n = v.size();
  std::vector<double> out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k <= 2 * m; ++k) out[i] += v[(i + n * (m + 1) + k - m) % n];
    out[i] /= static_cast<double>(2 * m + 1);
  }
  return out;
}
}  // namespace

// The surface layer's mean size by column (averaged across the bed), and at the crests and troughs: the
// highest and lowest quarter of the columns, both profiles smoothed over a quarter wavelength first.
// Single columns will not do: a coarse grain raises the column it settles in 27 times as much as a fine
// one (1.5 d against 0.5 d), so grain by grain, high columns are coarse whether or not ripples sort the
// sand; the smoothing keeps the ripple scale and drops that noise.
void RippleRun::surface_sizes(const SurfaceLayer& layer, BedFrame& f) const {
  const std::size_t nx = bed_.nx(), ny = bed_.ny();
  f.size_profile.assign(nx, 0.0);
  for (std::size_t k = 0; k < nx * ny; ++k)
    f.size_profile[k % nx] += layer.mean_size(k, o_.sizes) / static_cast<double>(ny);
  const double wavelength = f.stats.wavelength > 0 ? f.stats.wavelength : 8 * f.dx;
  const auto m = static_cast<std::size_t>(std::max(1.0, std::round(0.125 * wavelength / f.dx)));
  const std::vector<double> height = running_mean(f.profile, std::min(m, nx / 4)),
                            size = running_mean(f.size_profile, std::min(m, nx / 4));
  std::vector<std::size_t> order(nx);
  for (std::size_t i = 0; i < nx; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return height[a] < height[b]; });
  const std::size_t quarter = std::max<std::size_t>(1, nx / 4);
  double low = 0, high = 0;
  for (std::size_t q = 0; q < quarter; ++q) low += size[order[q]], high += size[order[nx - 1 - q]];
  f.size_trough = low / static_cast<double>(quarter), f.size_crest = high / static_cast<double>(quarter);
}

BedFrame RippleRun::frame() {
  BedFrame f;
  f.t_star = t_star();
  const double d = o_.diameter;
  f.h = bed_.heights();
  for (double& v : f.h) v /= d;
  const double dx = bed_.cell() / d;
  f.stats = bed_statistics(f.h, bed_.nx(), bed_.ny(), dx);
  f.dx = dx;
  f.profile.assign(bed_.nx(), 0.0);
  for (std::size_t j = 0; j < bed_.ny(); ++j)
    for (std::size_t i = 0; i < bed_.nx(); ++i)
      f.profile[i] += f.h[j * bed_.nx() + i] / static_cast<double>(bed_.ny());
  // Within half a wavelength (a quarter of the bed while there are no ripples) a shift is unambiguous.
  const double reach = f.stats.wavelength > 0 ? 0.5 * f.stats.wavelength : 0.25 * o_.length;
  f.shift = bed_shift(last_h_, f.h, bed_.nx(), bed_.ny(), dx, reach);
  if (samples_ > 0) f.mass_flux_star = q_sum_ / samples_, f.airborne = air_sum_ / samples_;
  if (samples_ > 0 && wind_sum_.size() == transport_->wind().z().size()) {
    WindProfile w{o_.u_star, transport_->wind().z(), wind_sum_};
    for (double& u : w.u) u /= samples_;
    const std::array<double, 2> band = frame_log_band(o_.height);
    f.z0 = log_layer_roughness(w, band[0] * d, band[1] * d).z0 / d;
  }
  wind_sum_.assign(wind_sum_.size(), 0.0);
  f.u_star_bed = std::sqrt(transport_->wind().bed_stress());
  f.loosening = transport_->loosening();
  if (const SurfaceLayer* layer = bed_.layer()) surface_sizes(*layer, f);
  const std::uint64_t collisions = transport_->total_collisions();  // (collective: every rank takes frames)
  if (f.t_star > frame_t_star_)
    f.collision_rate = static_cast<double>(collisions - frame_collisions_) / (f.t_star - frame_t_star_) /
                       (o_.length * o_.width / 1000);
  frame_collisions_ = collisions, frame_t_star_ = f.t_star;
  q_sum_ = air_sum_ = samples_ = 0;
  last_h_ = f.h;
  return f;
}

namespace {
SampleTable layer_table(const std::string& prefix, const SurfaceLayer& layer) {
  SampleTable t = grid_table(prefix + "layer",
                             "surface layer: each size class's volume as bed height (cm), "
                             "one row per key point",
                             layer.amounts(), layer.kinds());
  for (std::size_t c = 0; c < layer.kinds(); ++c) t.columns[c] = fmt::format("size{}", c);
  return t;
}
}  // namespace

std::vector<SampleTable> RippleRun::save(const std::string& prefix) const {
  std::vector<SampleTable> out = transport_->save(prefix + "transport/");
  const SampleTable bed = grid_table(prefix + "bed", "key-point heights (cm)", bed_.heights(), bed_.nx());
  const SampleTable last =
      grid_table(prefix + "last_frame", "heights at the previous frame (d)", last_h_, bed_.nx());
  SampleTable series{prefix + "series", "flux samples", {"t_star", "mass_flux_star", "airborne"}, {}};
  for (const auto& s : series_) series.rows.push_back({s[0], s[1], s[2]});
  SampleTable clock{prefix + "clock",
                    "bed counters and sums, next flux sample, sums since the last frame",
                    {"deposited", "eroded", "rolled", "pit_taken", "sum", "top", "next_sample", "q_sum",
                     "air_sum", "samples"},
                    {{static_cast<double>(bed_.deposited), static_cast<double>(bed_.eroded),
                      static_cast<double>(bed_.rolled), static_cast<double>(bed_.pit_taken), bed_.sum(),
                      bed_.top(), next_sample_, q_sum_, air_sum_, samples_}}};
  out.insert(out.end(), {bed, last, series, clock});
  if (const SurfaceLayer* layer = bed_.layer()) out.push_back(layer_table(prefix, *layer));
  return out;
}

void RippleRun::restore(const std::map<std::string, SampleTable>& tables, const std::string& prefix) {
  const auto& clock = checkpoint_table(tables, prefix + "clock", 10).rows;
  if (clock.size() != 1) throw std::invalid_argument("the checkpoint's run clock has no row");
  const auto& c = clock[0];
  const std::vector<double> h = grid_values(checkpoint_table(tables, prefix + "bed", bed_.nx()));
  bed_.restore(h,
               {static_cast<std::int64_t>(c[0]), static_cast<std::int64_t>(c[1]),
                static_cast<std::int64_t>(c[2]), static_cast<std::int64_t>(c[3])},
               c[4], c[5]);
  last_h_ = grid_values(checkpoint_table(tables, prefix + "last_frame", bed_.nx()));
  if (last_h_.size() != h.size()) throw std::invalid_argument("the checkpoint's last frame has another size");
  series_.clear();
  for (const auto& r : checkpoint_table(tables, prefix + "series", 3).rows)
    series_.push_back({r[0], r[1], r[2]});
  next_sample_ = c[6], q_sum_ = c[7], air_sum_ = c[8], samples_ = c[9];
  transport_->restore(tables, prefix + "transport/");
  if (SurfaceLayer* layer = bed_.layer())
    layer->restore(grid_values(checkpoint_table(tables, prefix + "layer", layer->kinds())));
  frame_collisions_ = transport_->total_collisions(), frame_t_star_ = t_star();  // checkpoints are at frames
}

std::array<double, 2> frame_log_band(double column_height) {
  return {std::min(300.0, 0.25 * column_height), std::min(1000.0, 0.85 * column_height)};
}

std::string shown_fit(double value) {
  return std::isfinite(value) ? fmt::format("{:.3g}", value) : std::string("n/a");
}

RippleTrends ripple_trends(const std::vector<BedFrame>& frames) {
  RippleTrends r;
  const std::size_t half = frames.size() / 2;
  std::vector<double> t, ln_a, ln_t, ln_l, wavelengths;
  std::vector<std::vector<double>> profiles;
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const BedFrame& f = frames[k];
    if (k <= half && f.stats.amplitude > 0)
      t.push_back(f.t_star), ln_a.push_back(std::log(f.stats.amplitude));
    if (k > half && f.stats.wavelength > 0) {
      ln_t.push_back(std::log(f.t_star)), ln_l.push_back(std::log(f.stats.wavelength));
      wavelengths.push_back(f.stats.wavelength);
    }
    if (k >= half && !f.profile.empty()) profiles.push_back(f.profile);
  }
  // Frames 1.. at the first interval, to within a step (the last one can be shorter when the duration is
  // not a multiple of it).
  if (frames.size() >= 4) {
    const double interval = frames[2].t_star - frames[1].t_star;
    std::vector<std::vector<double>> series;
    for (std::size_t k = 1; k < frames.size(); ++k) {
      if (k > 1 && std::abs(frames[k].t_star - frames[k - 1].t_star - interval) > 0.01 * interval) break;
      series.push_back(frames[k].profile);
    }
    r.response = band_response(series, frames.back().dx, interval);
  }
  double index_sum = 0, crest_sum = 0;
  std::size_t crest_frames = 0;
  for (const BedFrame& f : frames) {
    if (f.t_star < RippleTrends::kWindowStart - 1e-6 || f.t_star > RippleTrends::kWindowEnd + 1e-6) continue;
    // 0 means the frame has no wavelength (or no crests): undefined, not an index of zero.
    if (f.stats.ripple_index > 0) index_sum += f.stats.ripple_index, ++r.window_frames;
    if (f.stats.crest_ripple_index > 0) crest_sum += f.stats.crest_ripple_index, ++crest_frames;
  }
  if (r.window_frames > 0) r.window_ripple_index = index_sum / static_cast<double>(r.window_frames);
  if (crest_frames > 0) r.window_crest_ripple_index = crest_sum / static_cast<double>(crest_frames);
  r.growth_rate = least_squares_slope(t, ln_a);
  r.chi = least_squares_slope(ln_t, ln_l);
  r.migration_speed = std::nan("");
  if (profiles.size() >= 3 && !wavelengths.empty()) {
    std::sort(wavelengths.begin(), wavelengths.end());
    const double interval =
        (frames.back().t_star - frames[half].t_star) / static_cast<double>(profiles.size() - 1);
    r.migration_speed =
        profile_migration(profiles, frames.back().dx, 0.5 * wavelengths[wavelengths.size() / 2]) / interval;
  }
  return r;
}

}  // namespace grainlab::ripples::hybrid
