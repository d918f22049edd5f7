#include "lattice_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "surface_analysis.hpp"

namespace grainlab::ripples {

namespace {
constexpr double kColumn = 0.8660254037844386;  // sqrt(3) / 2: column width in grain diameters
constexpr double kLayer = 0.5, kRadius = 0.5;
constexpr int kBlock = 16;  // columns per block of the hit search
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
  const int base = 2 * (p.depth / 2);
  h_.resize(static_cast<std::size_t>(p.columns));
  // A close-packed flat top (the zig-zag of the top row), with random grains in some of its pockets.
  for (int i = 0; i < p.columns; ++i) h_[static_cast<std::size_t>(i)] = base + (i % 2);
  Rng start(p.seed, 1);
  for (int i = 0; i < p.columns; i += 2)
    if (start.uniform() < p.roughness) h_[static_cast<std::size_t>(i)] += 2;
  height_count_.assign(static_cast<std::size_t>(base + 64), 0);
  for (int v : h_) ++height_count_[static_cast<std::size_t>(v)], max_h_ = std::max(max_h_, v);
  block_max_.assign(static_cast<std::size_t>((p.columns + kBlock - 1) / kBlock), 0);
  for (int i = 0; i < p.columns; ++i) {
    int& top = block_max_[static_cast<std::size_t>(i / kBlock)];
    top = std::max(top, h_[static_cast<std::size_t>(i)]);
  }
}

int LatticeModel::near(int i) const {
  return i < 0 ? i + p_.columns : (i >= p_.columns ? i - p_.columns : i);
}

int LatticeModel::wrap(long i) const {
  const long n = p_.columns;
  return static_cast<int>(((i % n) + n) % n);
}

long LatticeModel::grains() const {
  long s = 0;
  for (int v : h_) s += v;
  return s;  // each grain adds 2 to one column: the sum changes only if grains appear or vanish
}

void LatticeModel::set(int i, int v) {
  int& h = h_[static_cast<std::size_t>(i)];
  const int old = h;
  --height_count_[static_cast<std::size_t>(old)];
  if (static_cast<std::size_t>(v) >= height_count_.size())
    height_count_.resize(static_cast<std::size_t>(v) + 64, 0);
  ++height_count_[static_cast<std::size_t>(v)];
  h = v;
  if (v > max_h_) max_h_ = v;
  while (height_count_[static_cast<std::size_t>(max_h_)] == 0) --max_h_;
  int& top = block_max_[static_cast<std::size_t>(i / kBlock)];
  if (v > top) {
    top = v;
  } else if (old == top && v < old) {
    const int b = (i / kBlock) * kBlock, e = std::min(b + kBlock, p_.columns);
    top = *std::max_element(h_.begin() + b, h_.begin() + e);
  }
}

// The first surface grain the path from (start_x, above every grain) meets, scanning downstream. `p` gets
// the signed distance of the path from that grain's centre (perpendicular to the path). Blocks of columns
// the path passes above (judged by their highest grain) are skipped whole: the same hit, found faster.
int LatticeModel::hit_column(double start_x, double& p) {
  const int n = p_.columns;
  // The first column at or after start_x (0 <= start_x < the domain's length, so no modulo is needed).
  const int first = static_cast<int>(start_x * (1 / kColumn)) + 1;
  const double step = tan_a_ * kColumn, reach = kRadius / cos_a_;
  // The path's height at the column under test, relative to the layer grid: hit when it passes less than
  // one radius (perpendicular to the path) above the column's top grain centre.
  double ray = max_h_ * kLayer + 2 * kRadius - tan_a_ * (first * kColumn - start_x);
  int i = first >= n ? first - n : first;
  for (;;) {
    const int block = i / kBlock, last = std::min((block + 1) * kBlock, n) - 1;
    if (ray - step * (last - i) - block_max_[static_cast<std::size_t>(block)] * kLayer >= reach) {
      ray -= step * (last - i + 1);
      i = last + 1 == n ? 0 : last + 1;
      continue;
    }
    for (; i <= last; ++i, ray -= step) {
      const double above = ray - h_[static_cast<std::size_t>(i)] * kLayer;
      if (above < reach) {
        p = above * cos_a_;
        return i;
      }
    }
    if (i == n) i = 0;
  }
}

// Where a dropped grain rests: a pocket (a column lower than both neighbours). From a slope it rolls down;
// from a crest it goes on in the direction it was moving.
void LatticeModel::drop(int c, int direction) {
  for (;;) {
    const int h = h_[static_cast<std::size_t>(c)];
    const int left = h_[static_cast<std::size_t>(near(c - 1))],
              right = h_[static_cast<std::size_t>(near(c + 1))];
    if (left > h && right > h) {
      set(c, h + 2);
      return;
    }
    const int step = left < h && right < h ? direction : (left < h ? -1 : 1);
    c = near(c + step);
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
  // A window of four heights slides along `direction` (one load per column): at offset k it holds the
  // columns k - 1, k, k + 1 and k + 2 steps on.
  // (near() wraps by one domain length, enough while the look-ahead stays below it, as configs ensure.)
  auto at = [&](int k) { return h_[static_cast<std::size_t>(near(from + direction * k))]; };
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
  for (;;) {
    const int h = h_[static_cast<std::size_t>(c)];
    if (h_[static_cast<std::size_t>(near(c - 1))] > h && h_[static_cast<std::size_t>(near(c + 1))] > h) {
      set(c, h + 2);
      return;
    }
    c = near(c + direction);
  }
}

void LatticeModel::eject(int column, int direction, int hop_columns) {
  remove_top(column);
  const int at = wrap(column + direction * hop_columns);
  if (p_.land_downhill)
    drop(at, direction);
  else
    land_onward(at, direction);
  (direction > 0 ? forward_ : backward_)++;
}

void LatticeModel::fire(long impacts) {
  const double length = p_.columns * kColumn;
  for (long n = 0; n < impacts;) {
    const double x0 = rng_.uniform() * length;
    for (int k = 0; k < p_.hits_per_point && n < impacts; ++k, ++n, ++impacts_) {
      double p = 0;
      const int c = hit_column(x0, p);
      // The contact point lies downstream of the grain's centre when the path grazes its top
      // (p sin a > sqrt(R^2 - p^2) cos a): then the grain is hit on its downstream side.
      const double sin_a = tan_a_ * cos_a_;
      const bool downstream = p * sin_a > std::sqrt(std::max(0.0, kRadius * kRadius - p * p)) * cos_a_;
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
