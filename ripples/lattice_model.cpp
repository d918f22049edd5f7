#include "lattice_model.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "surface_analysis.hpp"

namespace grainlab::ripples {

namespace {
constexpr double kColumn = 0.8660254037844386;  // sqrt(3) / 2: column width in grain diameters
constexpr double kLayer = 0.5, kRadius = 0.5;
constexpr int kBlock = 64;  // columns per block of the hit search
}  // namespace

LatticeModel::LatticeModel(const LatticeParams& p)
    : p_(p),
      rng_(p.seed, 0),
      tan_a_(std::tan(p.impact_deg * M_PI / 180)),
      cos_a_(std::cos(p.impact_deg * M_PI / 180)) {
  if (2L * std::max(p.forward, p.backward) >= p.columns || 2L * p.brink_lookahead + 4 >= p.columns)
    throw std::invalid_argument("hops and the brink look-ahead must be shorter than the lattice");
  if (p.columns < 16 || p.columns % 2)
    throw std::invalid_argument("the lattice needs an even number >= 16 of columns");
  if (p.initial_amplitude > 0 && p.roughness > 0)
    throw std::invalid_argument("a seeded sine and a rough start exclude each other");
  const int base = 2 * (p.depth / 2);
  if (p.initial_amplitude > 0) {
    seed_sine(base);
  } else {
    // A close-packed flat top (the zig-zag of the top row), with random grains in some of its pockets.
    h_.resize(static_cast<std::size_t>(p.columns));
    for (int i = 0; i < p.columns; ++i) h_[static_cast<std::size_t>(i)] = base + (i % 2);
    Rng start(p.seed, 1);
    for (int i = 0; i < p.columns; i += 2)
      if (start.uniform() < p.roughness) h_[static_cast<std::size_t>(i)] += 2;
  }
  max_h_ = *std::max_element(h_.begin(), h_.end());
  rise_.assign(static_cast<std::size_t>((p.columns + 2 * kPad) / 64 + 2), 0);
  for (int j = 0; j < p.columns; ++j)
    put_rise(j, h_[static_cast<std::size_t>(near(j + 1))] > h_[static_cast<std::size_t>(j)]);
  step_ = tan_a_ * kColumn;
  g_.resize(h_.size());
  block_g_.assign(static_cast<std::size_t>((p.columns + kBlock - 1) / kBlock), -HUGE_VAL);
  for (int i = 0; i < p.columns; ++i) {
    g_[static_cast<std::size_t>(i)] = ray_invariant(i, h_[static_cast<std::size_t>(i)]);
    double& top = block_g_[static_cast<std::size_t>(i / kBlock)];
    top = std::max(top, g_[static_cast<std::size_t>(i)]);
  }
}

// The walk nearest base + 1/2 + A sin(2 pi waves i / columns): each step goes toward the next column's
// target. It stays within a layer of the target, so on a closed (periodic) target the last column ends
// one layer from the first, as the walk requires (checked).
void LatticeModel::seed_sine(int base) {
  const int n = p_.columns, waves = lattice_seeded_waves(p_);
  if (2 * p_.initial_amplitude * std::sin(M_PI * waves / n) >= 1)
    throw std::invalid_argument("the seeded sine is steeper than the lattice's 30 deg repose slope");
  auto target = [&](int i) { return base + 0.5 + p_.initial_amplitude * std::sin(2 * M_PI * waves * i / n); };
  h_.assign(static_cast<std::size_t>(n), base);
  for (int i = 1; i < n; ++i) {
    const int prev = h_[static_cast<std::size_t>(i - 1)];
    h_[static_cast<std::size_t>(i)] = prev < target(i) ? prev + 1 : prev - 1;
  }
  if (std::abs(h_.back() - h_.front()) != 1) throw std::logic_error("the seeded walk does not close");
}

int lattice_seeded_waves(const LatticeParams& p) {
  if (p.initial_wavelength <= 0) return 1;
  return std::max(1, static_cast<int>(std::lround(p.columns / (2 * p.initial_wavelength))));
}

std::complex<double> lattice_mode(const std::vector<int>& h, int waves) {
  const std::size_t n = h.size();
  std::complex<double> a = 0;
  for (std::size_t i = 0; i < n; ++i)
    a += static_cast<double>(h[i]) * std::polar(1.0, -2 * M_PI * waves * static_cast<double>(i) / n);
  return a * (2.0 / n);
}

std::complex<double> lattice_linear_rate(double impact_deg, double forward, double backward, double b,
                                         double wavelength) {
  const double c = 1 / (2 * std::sqrt(3.0) * std::tan(impact_deg * M_PI / 180)), k = 2 * M_PI / wavelength;
  const double grow = c * k * ((1 - b) * std::sin(k * forward) - b * std::sin(k * backward));
  const double speed = c * (1 - (1 - b) * std::cos(k * forward) - b * std::cos(k * backward));
  return {grow, -k * speed};
}

LatticeResponse lattice_linear_response(LatticeParams p, double tau, int frames, int seeds) {
  if (p.initial_amplitude <= 0 || frames < 2 || seeds < 1 || tau <= 0)
    throw std::invalid_argument("the linear response needs a seeded sine, frames >= 2, seeds >= 1, tau > 0");
  const int waves = lattice_seeded_waves(p);
  std::vector<std::complex<double>> mode(static_cast<std::size_t>(frames) + 1);
  long forward = 0, backward = 0;
  const std::uint64_t first = p.seed;
  for (int s = 0; s < seeds; ++s) {
    p.seed = first + static_cast<std::uint64_t>(s);
    LatticeModel m(p);
    mode[0] += lattice_mode(m.heights(), waves) / double(seeds);
    long fired = 0;
    for (int f = 1; f <= frames; ++f) {
      const long upto = std::lround(tau * f / frames * p.columns / 2);
      m.fire(upto - fired), fired = upto;
      mode[static_cast<std::size_t>(f)] += lattice_mode(m.heights(), waves) / double(seeds);
    }
    forward += m.forward_hops(), backward += m.backward_hops();
  }
  LatticeResponse r;
  r.wavelength = p.columns / 2.0 / waves;
  const double k = 2 * M_PI / r.wavelength;
  std::vector<double> t, log_a, phase;
  double unwrapped = std::arg(mode[0]);
  for (int f = 0; f <= frames; ++f) {
    const std::complex<double> a = mode[static_cast<std::size_t>(f)];
    if (f > 0)
      unwrapped += std::remainder(std::arg(a) - std::arg(mode[static_cast<std::size_t>(f - 1)]), 2 * M_PI);
    t.push_back(tau * f / frames), log_a.push_back(std::log(std::abs(a))), phase.push_back(unwrapped);
  }
  r.growth = least_squares_slope(t, log_a);
  r.speed = -least_squares_slope(t, phase) / k;  // a exp(-i k c tau): a crest moving downstream at c
  r.backward_share = forward + backward > 0 ? double(backward) / double(forward + backward) : 0;
  const std::complex<double> s =
      lattice_linear_rate(p.impact_deg, p.forward, p.backward, r.backward_share, r.wavelength);
  r.theory_growth = s.real(), r.theory_speed = -s.imag() / k;
  r.amplitude_start = std::abs(mode.front()), r.amplitude_end = std::abs(mode.back());
  return r;
}

int LatticeModel::near(int i) const {
  return i < 0 ? i + p_.columns : (i >= p_.columns ? i - p_.columns : i);
}

long LatticeModel::grains() const {
  long s = 0;
  for (int v : h_) s += v;
  return s;  // each grain adds 2 to one column: the sum changes only if grains appear or vanish
}

void LatticeModel::set(int i, int v) {
  const int n = p_.columns, left = near(i - 1);
  h_[static_cast<std::size_t>(i)] = v;
  const bool left_up = v > h_[static_cast<std::size_t>(left)],
             right_up = h_[static_cast<std::size_t>(near(i + 1))] > v;
  if (i > kPad && i < n - kPad - 1) {  // the usual case: two bits, no copies in the margins
    write_bit(i - 1 + kPad, left_up);
    write_bit(i + kPad, right_up);
  } else {
    put_rise(left, left_up);
    put_rise(i, right_up);
  }
  max_h_ = std::max(max_h_, v);
  double& g = g_[static_cast<std::size_t>(i)];
  const double old_g = g;
  g = ray_invariant(i, v);
  double& top = block_g_[static_cast<std::size_t>(i / kBlock)];
  if (g > top) {
    top = g;
  } else if (old_g == top && g < old_g) {
    const int b = (i / kBlock) * kBlock, e = std::min(b + kBlock, p_.columns);
    top = *std::max_element(g_.begin() + b, g_.begin() + e);
  }
}

// The first surface grain the path from (start_x, above every grain) meets, scanning downstream. `p` gets
// the signed distance of the path from that grain's centre (perpendicular to the path). The start's
// height is max_h_ d / 2 + 2 R, max_h_ an upper bound on the surface: starting higher by any fixed amount
// moves every path's start the same distance upstream, which leaves the hits of uniformly random starts on
// a periodic bed distributed as before.
// The path's height at column i is top + tan a start_x - step i, and it hits the column's top grain when
// it passes less than `reach` (one radius, perpendicular to the path) above its centre h_i d / 2, i.e.
// when the column's ray invariant g_i = h_i d / 2 + step i exceeds c = top + tan a start_x - reach: one
// comparison per column, and whole blocks whose largest g the path clears are skipped. Past the domain's
// end the path continues at column 0 with its unwrapped index i + n, i.e. with c lowered by step n.
int LatticeModel::hit_column(double start_x, double& p) {
  const int n = p_.columns;
  const double reach = kRadius / cos_a_;
  double c = max_h_ * kLayer + 2 * kRadius + tan_a_ * start_x - reach;
  // The first column at or after start_x (0 <= start_x < the domain's length, so no modulo is needed).
  int i = static_cast<int>(start_x * (1 / kColumn)) + 1;
  if (i >= n) i -= n, c -= step_ * n;
  const double* g = g_.data();
  for (;;) {
    const int last = std::min((i / kBlock + 1) * kBlock, n) - 1;
    if (block_g_[static_cast<std::size_t>(i / kBlock)] > c) {
      for (; i <= last; ++i)
        if (g[i] > c) {
          p = (c + reach - g[i]) * cos_a_;
          return i;
        }
    }
    i = last + 1;
    if (i == n) i = 0, c -= step_ * n;
  }
}

// Where a dropped grain rests: a pocket (a column lower than both neighbours). From a slope it rolls down;
// from a crest it goes on in the direction it was moving.
// Neighbouring columns never have equal heights (their layer indices differ in parity), so the way down
// is the same all the way to the pocket: the first pocket on that side.
void LatticeModel::drop(int c, int direction) {
  const bool left_lower = rises(near(c - 1)), right_lower = !rises(c);
  if (left_lower && right_lower)
    land_at(first_pocket(c, direction));
  else if (left_lower || right_lower)
    land_at(first_pocket(c, left_lower ? -1 : 1));
  else
    land_at(c);
}

void LatticeModel::land_at(int c) {
  set(c, h_[static_cast<std::size_t>(c)] + 2);
}

bool LatticeModel::rises(int j) const {
  const int b = j + kPad;
  return (rise_[static_cast<std::size_t>(b >> 6)] >> (b & 63)) & 1;
}

// 64 slope bits from column j on: bit b tells whether column j + b + 1 is higher than column j + b
// (-kPad <= j, j + 64 <= n + kPad).
std::uint64_t LatticeModel::rise_bits(int j) const {
  const int b = j + kPad, s = b & 63;
  const std::uint64_t* w = rise_.data() + (b >> 6);
  return s ? (w[0] >> s) | (w[1] << (64 - s)) : w[0];
}

// Column j's slope bit (column j + 1 higher than j), stored at j + kPad and at every position that
// stands for column j in the wrapped margins.
void LatticeModel::put_rise(int j, bool up) {
  const int n = p_.columns, total = n + 2 * kPad;
  auto put = [&](int b) { write_bit(b, up); };
  if (n >= 2 * kPad) {  // one copy in the middle, another in a margin for the columns near the ends
    put(j + kPad);
    if (j < kPad) put(j + kPad + n);
    if (j >= n - kPad) put(j + kPad - n);
    return;
  }
  int first = j + kPad;
  while (first >= n) first -= n;
  for (int b = first; b < total; b += n) put(b);
}

// The first pocket (a column lower than both neighbours: its left slope falls, its own rises) at or after
// column c in `direction`, 63 columns per word test.
int LatticeModel::first_pocket(int c, int direction) const {
  for (;;) {
    if (direction > 0) {
      const std::uint64_t w = rise_bits(c - 1), pockets = ~w & (w >> 1);  // bit m: pocket at c + m
      if (pockets) return near(c + std::countr_zero(pockets));
      c = near(c + 63);
    } else {
      const std::uint64_t w = rise_bits(c - 63), pockets = ~w & (w >> 1);  // bit b: pocket at c - 62 + b
      if (pockets) return near(c - 62 + (63 - std::countl_zero(pockets)));
      c = near(c - 63);
    }
  }
}

// Takes the top grain off column i, then lets every grain that lost its support roll to the next pocket
// below it (the lattice's avalanche: the slope above shifts down by one grain).
void LatticeModel::remove_top(int i) {
  set(i, h_[static_cast<std::size_t>(i)] - 2);
  std::vector<int>& check = unstable_;
  check.assign(1, i);
  while (!check.empty()) {
    const int c = check.back();
    check.pop_back();
    for (int side : {-1, 1}) {
      const int n = near(c + side);
      if (h_[static_cast<std::size_t>(n)] - h_[static_cast<std::size_t>(c)] != 3) continue;
      set(n, h_[static_cast<std::size_t>(n)] - 2);
      drop(c, -side);
      check.push_back(n);
      check.push_back(c);
    }
  }
}

// The first brink within `limit` columns of `from` in `direction`: a crest grain (higher than both
// neighbours) beyond which the surface keeps falling (two columns on it is two layers lower), i.e. the top
// of a face. The crests of a flat close-packed top are not brinks, so brink ejection leaves it alone.
// -1 if none.
int LatticeModel::find_brink(int from, int direction, int limit) const {
  // At rest neighbouring columns differ by one layer, so a brink is a rise into a column followed by two
  // falls: three slope bits, tested for the whole look-ahead at once.
  if (limit <= 61) {
    const std::uint64_t in_reach = (std::uint64_t{2} << limit) - 1;
    if (direction > 0) {
      const std::uint64_t w = rise_bits(from - 1), brinks = w & ~(w >> 1) & ~(w >> 2) & in_reach;
      return brinks ? near(from + std::countr_zero(brinks)) : -1;
    }
    // bit b: slopes from - limit - 2 + b (rising), + 1 (rising), + 2 (falling): a brink at from - limit + b
    const std::uint64_t w = rise_bits(from - limit - 2), brinks = w & (w >> 1) & ~(w >> 2) & in_reach;
    return brinks ? near(from - limit + (63 - std::countl_zero(brinks))) : -1;
  }
  // A look-ahead longer than a word: a window of four heights slides along `direction` (one load per
  // column); at offset k it holds the columns k - 1, k, k + 1 and k + 2 steps on. (near() wraps by one
  // domain length, enough while the look-ahead stays below it, as configs ensure.)
  const int* h = h_.data();
  auto at = [&](int k) { return h[near(from + direction * k)]; };
  int prev = at(-1), cur = at(0), next = at(1), next2 = at(2);
  for (int k = 0; k <= limit; ++k) {
    if (prev < cur && next < cur && next2 <= cur - 2) return near(from + direction * k);
    prev = cur, cur = next, next = next2, next2 = at(k + 3);
  }
  return -1;
}

// The thesis's landing rule: a hopping grain that does not land in a pocket moves on in its direction of
// motion until it finds one (over a crest if need be).
void LatticeModel::land_onward(int c, int direction) {
  land_at(first_pocket(c, direction));
}

void LatticeModel::eject(int column, int direction, int hop_columns) {
  remove_top(column);
  const int at = near(column + direction * hop_columns);  // hops are shorter than the domain
  if (p_.land_downhill)
    drop(at, direction);
  else
    land_onward(at, direction);
  (direction > 0 ? forward_ : backward_)++;
}

void LatticeModel::fire(long impacts) {
  const double length = p_.columns * kColumn;
  for (long n = 0; n < impacts;) {
    // max_h_ only rises between these exact recounts: any height above the bed serves as the paths'
    // start (see hit_column), a close one saves the search some blocks.
    if (impacts_ >= next_recount_) {
      max_h_ = *std::max_element(h_.begin(), h_.end());
      next_recount_ = impacts_ + 4096;
    }
    const double x0 = rng_.uniform() * length;
    for (int k = 0; k < p_.hits_per_point && n < impacts; ++k, ++n, ++impacts_) {
      double p = 0;
      const int c = hit_column(x0, p);
      // The contact point lies downstream of the grain's centre when the path grazes its top
      // (p sin a > sqrt(R^2 - p^2) cos a, i.e. p > R cos a for |p| < R): then the grain is hit on its
      // downstream side.
      const bool downstream = p > kRadius * cos_a_;
      int direction = downstream ? -1 : 1;
      int hop = 2 * (downstream ? p_.backward : p_.forward);
      if (!p_.hops_d.empty()) {  // splash mode: the hop, and its direction, drawn from the measured ones
        const double L = p_.hops_d[std::min(p_.hops_d.size() - 1,
                                            static_cast<std::size_t>(rng_.uniform() * p_.hops_d.size()))];
        direction = L < 0 ? -1 : 1;
        hop = std::min(static_cast<int>(std::lround(std::abs(L) / kColumn)), p_.columns / 2 - 1);
      }
      if (p_.brink_probability > 0 && rng_.uniform() < p_.brink_probability) {
        const int brink = find_brink(c, direction, 2 * p_.brink_lookahead);
        if (brink >= 0) eject(brink, direction, hop);
      } else if (hop > 0) {
        eject(c, direction, hop);
      }
    }
  }
}

LatticeLengthScales lattice_length_scales(const std::vector<int>& h) {
  std::vector<double> y;
  for (std::size_t i = 0; i < h.size(); i += 2) y.push_back(h[i]);  // one column per lattice spacing
  LatticeLengthScales r;
  r.f = length_scale_distribution(y, std::max<int>(1, static_cast<int>(y.size() / 4)), 2.0);
  r.f_peak = length_scale_peak(r.f);
  r.autocorrelation_wavelength = autocorrelation_wavelength(y);
  return r;
}

LatticeSurfaceStats lattice_surface_stats(const std::vector<int>& h, int smooth) {
  LatticeSurfaceStats s;
  const int n = static_cast<int>(h.size());
  if (n < 4) return s;
  // A running mean over 2 smooth + 1 columns removes the zig-zag; then the shape in grain diameters, with
  // crests and troughs at least one layer proud.
  std::vector<double> y(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    double sum = 0;
    for (int k = -smooth; k <= smooth; ++k) sum += h[static_cast<std::size_t>(((i + k) % n + n) % n)];
    y[static_cast<std::size_t>(i)] = sum / (2 * smooth + 1) * kLayer;
  }
  const SurfaceShape shape = surface_shape(y, kColumn, kLayer);
  double mean = 0, var = 0;
  for (int v : h) mean += v;
  mean /= n;
  for (int v : h) var += (v - mean) * (v - mean);
  s.rms = std::sqrt(var / n);
  s.crests = shape.crests;
  s.wavelength = shape.wavelength / (2 * kColumn);  // lattice spacings
  s.height = shape.height / kLayer;                 // layers
  s.stoss_deg = shape.stoss_deg, s.lee_deg = shape.lee_deg;
  return s;
}

}  // namespace grainlab::ripples
