#include "airborne.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace grainlab::ripples::hybrid {

void Grains::remove_marked(const std::vector<char>& drop) {
  std::size_t keep = 0;
  for (std::size_t i = 0; i < size(); ++i) {
    if (i < drop.size() && drop[i]) continue;
    if (keep != i)
      x[keep] = x[i], y[keep] = y[i], z[keep] = z[i], vx[keep] = vx[i], vy[keep] = vy[i], vz[keep] = vz[i],
      kind[keep] = kind[i], id[keep] = id[i], splash[keep] = splash[i];
    ++keep;
  }
  truncate(keep);
}

void Grains::truncate(std::size_t n) {
  for (auto* v : {&x, &y, &z, &vx, &vy, &vz}) v->resize(n);
  kind.resize(n), id.resize(n), splash.resize(n);
}

// From the back, in place: the grains past the first arrival's place move once, the rest stay (no copy
// of the whole set every step a grain arrives).
void Grains::merge(const Grains& more) {
  const std::size_t n = size(), k = more.size();
  if (k == 0) return;
  truncate(n + k);
  std::size_t a = n, b = k, w = n + k;
  auto put = [this, &w](const Grains& g, std::size_t i) {
    x[w] = g.x[i], y[w] = g.y[i], z[w] = g.z[i], vx[w] = g.vx[i], vy[w] = g.vy[i], vz[w] = g.vz[i];
    kind[w] = g.kind[i], id[w] = g.id[i], splash[w] = g.splash[i];
  };
  while (b > 0) {
    --w;
    if (a > 0 && id[a - 1] > more.id[b - 1])
      put(*this, --a);
    else
      put(more, --b);
  }
}

void pack_grain(const Grains& g, std::size_t i, std::vector<double>& out) {
  out.insert(out.end(), {static_cast<double>(g.id[i]), g.x[i], g.y[i], g.z[i], g.vx[i], g.vy[i], g.vz[i],
                         static_cast<double>(g.kind[i]), splash_value(g.splash[i])});
}

void unpack_grains(const double* v, std::size_t count, Grains& into) {
  for (std::size_t k = 0; k < count; ++k, v += kGrainValues)
    into.add(v[1], v[2], v[3], v[4], v[5], v[6], static_cast<int>(v[7]), static_cast<std::uint64_t>(v[0]),
             splash_number(v[8]));
}

CollisionGrid::CollisionGrid(double length, double width, double d, double cell_x, double cell_y)
    : nx_(std::max(3L, static_cast<long>(length / std::max(d, cell_x)))),
      ny_(std::max(3L, static_cast<long>(width / std::max(d, cell_y)))),
      inv_hx_(static_cast<double>(nx_) / length),
      inv_hy_(static_cast<double>(ny_) / width),
      d_(d),
      length_(length),
      width_(width) {
  set_blocks(1);
  bit_row_ = static_cast<std::size_t>(ny_ + 2);
  occupied_.assign((static_cast<std::size_t>(nx_ + 1) * bit_row_ + 7) / 8 + sizeof(std::uint64_t), 0);
}

inline void CollisionGrid::Occupancy::mark(long ix, long iy, bool on) const {
  auto put = [&](std::size_t at) {
    const auto mask = static_cast<std::uint8_t>(1u << (at % 8));
    on ? bytes[at / 8] |= mask : bytes[at / 8] &= static_cast<std::uint8_t>(~mask);
  };
  // The edge columns' repeated bits: chosen, not branched to, since on a narrow bed a fifth of the grains
  // sit at an edge in no order a branch predictor could learn. Elsewhere the bit is put twice.
  auto in_row = [&](long x) {
    const std::size_t at = bit(x, iy) + 1, n = static_cast<std::size_t>(ny);
    put(at);
    put(iy == 0 ? at + n : (iy == ny - 1 ? at - n : at));
  };
  in_row(ix);
  if (ix == 0) in_row(nx);
}

inline std::uint64_t CollisionGrid::Occupancy::from(std::size_t at) const {
  std::uint64_t word;
  std::memcpy(&word, bytes + at / 8, sizeof word);
  return word >> (at % 8);
}

void CollisionGrid::set_blocks(long blocks) {
  blocks_ = std::clamp(blocks, 1L, std::max(1L, nx_ / 2));
  edge_.assign(static_cast<std::size_t>(nx_), 0);
  for (long x = 0; x < nx_; ++x)
    edge_[static_cast<std::size_t>(x)] = block_of(x) != block_of(wrap(x + 1, nx_));
}

void CollisionGrid::set_sizes(std::vector<double> diameters, std::vector<double> masses) {
  diameters_ = std::move(diameters), masses_ = std::move(masses);
}

std::uint64_t CollisionGrid::collide_all(Grains& g, double m, const CollisionLaw& law) {
  return diameters_.empty() ? collide_as<false>(g, m, law) : collide_as<true>(g, m, law);
}

// Once per bed (one size or several), so grains of one size pay nothing for the size lookup.
template <bool kMixed>
std::uint64_t CollisionGrid::collide_as(Grains& g, double m, const CollisionLaw& law) {
  const std::size_t n = g.size();
  if (head_.empty()) head_.assign(static_cast<std::size_t>(nx_ * ny_), kNone);
  next_.resize(n), column_x_.resize(n), column_y_.resize(n);
  forget_shifts();  // (left by a pass whose shifts were not applied)
  for (std::uint32_t i = 0; i < n; ++i) {
    const long ix = std::min(nx_ - 1, static_cast<long>(g.x[i] * inv_hx_));
    const long iy = std::min(ny_ - 1, static_cast<long>(g.y[i] * inv_hy_));
    column_x_[i] = static_cast<std::uint32_t>(ix), column_y_[i] = static_cast<std::uint32_t>(iy);
  }
  // The grains come in id order, not in order of place: on a wide bed the chain heads are then written
  // all over an array larger than the cache. Each grain's head is fetched a few grains ahead. (The
  // search below reads a head only where the bits say a column is occupied: fetching those ahead, too,
  // measured slower.)
  constexpr std::uint32_t kAheadOf = 8;
  const Occupancy bits = occupancy();
  std::uint32_t* const head = head_.data();
  std::uint32_t* const next = next_.data();
  const std::uint32_t *const column_x = column_x_.data(), *const column_y = column_y_.data();
  const long nx = nx_, ny = ny_;
  auto column = [&](std::uint32_t i) { return static_cast<std::size_t>(column_x[i]) * ny + column_y[i]; };
  // (Only where the heads outgrow the cache's second level: on a smaller bed they are there already.)
  const std::uint32_t fetched = head_.size() * sizeof(std::uint32_t) > (std::size_t{1} << 18) ? n : 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (i + kAheadOf < fetched) __builtin_prefetch(&head[column(i + kAheadOf)], 1);
    const std::size_t c = column(i);
    const long ix = column_x[i], iy = column_y[i];
    next[i] = bits.test(bits.bit(ix, iy) + 1) ? head[c] : kNone;
    head[c] = i;
    bits.mark(ix, iy, true);
  }
  std::uint64_t hits = 0;
  static constexpr long kAhead[4][2] = {{1, -1}, {1, 0}, {1, 1}, {0, 1}};
  across_.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    for (std::uint32_t j = next[i]; j != kNone; j = next[j]) hits += pair<kMixed>(g, i, j, m, law);
    const long ix = column_x[i], iy = column_y[i];
    // kAhead's four columns: bits iy .. iy + 2 of row ix + 1, and bit iy + 2 of row ix.
    const std::size_t at = bits.bit(ix, iy);
    // All four are empty in the usual case. Otherwise the occupied ones (an empty column's head is stale:
    // not cleared after a pass), in kAhead's order, by their bits.
    const std::uint64_t ahead = (bits.from(at + bits.row) & 7) | (bits.from(at + 2) & 1) << 3;
    const bool edge = edge_[static_cast<std::size_t>(ix)];
    for (std::uint64_t rest = ahead; rest != 0; rest &= rest - 1) {
      const auto& off = kAhead[std::countr_zero(rest)];
      const auto o = static_cast<std::size_t>(wrap(ix + off[0], nx) * ny + wrap(iy + off[1], ny));
      for (std::uint32_t j = head[o]; j != kNone; j = next[j])
        if (!edge || off[0] == 0)
          hits += pair<kMixed>(g, i, j, m, law);
        else if (Separation s; sweep_ > 0 || overlap<kMixed>(g, i, j, s))  // across a block boundary:
          across_.emplace_back(i, j);  // after all within (swept: every candidate, as velocities change)
    }
  }
  // Whichever is less work: a bit array of up to 64 bytes per grain is cleared whole (one pass of
  // stores), a larger one (a nearly empty bed) grain by grain.
  if (occupied_.size() <= 64 * n)
    std::fill(occupied_.begin(), occupied_.end(), std::uint8_t{0});
  else
    for (std::uint32_t i = 0; i < n; ++i) bits.mark(column_x[i], column_y[i], false);
  for (const auto& [i, j] : across_) hits += pair<kMixed>(g, i, j, m, law);
  return hits;
}

std::uint64_t CollisionGrid::collide_across(Grains& g, const std::vector<std::uint32_t>& left,
                                            const std::vector<std::uint32_t>& right, double m,
                                            const CollisionLaw& law, bool count) {
  std::uint64_t hits = 0;
  for (const std::uint32_t i : left) {
    const long iy = column_y(g.y[i]);
    for (long dy = -1; dy <= 1; ++dy) {
      const long y = wrap(iy + dy, ny_);
      for (std::size_t k = right.size(); k-- > 0;) {  // a column's chain runs from its highest id down
        const std::uint32_t j = right[k];
        if (column_y(g.y[j]) == y)
          hits += diameters_.empty() ? pair<false>(g, i, j, m, law) : pair<true>(g, i, j, m, law);
      }
    }
  }
  return count ? hits : 0;
}

std::uint64_t CollisionGrid::collide_pairs(Grains& g,
                                           const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                                           double m, const CollisionLaw& law, std::vector<double>& shifts,
                                           std::vector<std::uint32_t>& touched) {
  // The grains here are not those collide_all's shifts are indexed by: those wait in a store of their own.
  std::vector<std::uint32_t> shifted, slot;
  std::vector<double> shift;
  std::swap(shifted, shifted_), std::swap(slot, slot_), std::swap(shift, shift_);
  std::uint64_t hits = 0;
  touched.clear();
  for (const auto& [i, j] : pairs)
    if (diameters_.empty() ? pair<false>(g, i, j, m, law) : pair<true>(g, i, j, m, law))
      ++hits, touched.push_back(i), touched.push_back(j);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  shifts.assign(3 * g.size(), 0.0);
  for (std::size_t n = 0; n < shifted_.size(); ++n)
    for (std::size_t k = 0; k < 3; ++k) shifts[3 * shifted_[n] + k] = shift_[3 * n + k];
  std::swap(shifted, shifted_), std::swap(slot, slot_), std::swap(shift, shift_);
  return hits;
}

template <bool kMixed>
bool CollisionGrid::overlap(const Grains& g, std::size_t i, std::size_t j, Separation& s) const {
  double reach = d_;
  if constexpr (kMixed) reach = 0.5 * (diameters_[g.kind[i]] + diameters_[g.kind[j]]);
  if (sweep_ > 0) return swept_contact<kMixed>(g, i, j, reach, s);
  // The whole distance, then one test: whether a candidate pair is a height apart is a coin toss a branch
  // would mispredict, whether it overlaps is nearly always no.
  s.dz = g.z[j] - g.z[i];
  s.dx = nearest(g.x[j] - g.x[i], length_), s.dy = nearest(g.y[j] - g.y[i], width_);
  s.r2 = s.dx * s.dx + s.dy * s.dy + s.dz * s.dz;
  return (s.r2 < reach * reach) & (s.r2 > 0);
}

// The separation b seconds ago is r - w b (r now, w the relative velocity): they touch where
// a b^2 - 2 B b + c = 0 (a = w.w, B = r.w, c = r.r - reach^2); the first contact is the larger root.
template <bool kMixed>
bool CollisionGrid::swept_contact(const Grains& g, std::size_t i, std::size_t j, double reach,
                                  Separation& s) const {
  const double wz = g.vz[j] - g.vz[i], dz = g.z[j] - g.z[i], dz_start = dz - wz * sweep_;
  if ((dz >= reach && dz_start >= reach) || (dz <= -reach && dz_start <= -reach)) return false;
  const double dx = nearest(g.x[j] - g.x[i], length_), dy = nearest(g.y[j] - g.y[i], width_);
  const double wx = g.vx[j] - g.vx[i], wy = g.vy[j] - g.vy[i];
  const double a = wx * wx + wy * wy + wz * wz, b = dx * wx + dy * wy + dz * wz;
  const double c = dx * dx + dy * dy + dz * dz - reach * reach;
  if (c >= 0) {                            // apart now: were they closer than reach within the span?
    if (!(a > 0) || b <= 0) return false;  // nearest now
    const double nearest_at = std::min(b / a, sweep_);
    if (c - nearest_at * (2 * b - a * nearest_at) >= 0) return false;
  }
  const double root = a > 0 ? (b + std::sqrt(std::max(0.0, b * b - a * c))) / a : 0;
  s.back = std::min(root, sweep_);
  s.dx = dx - wx * s.back, s.dy = dy - wy * s.back, s.dz = dz - wz * s.back;
  s.r2 = s.dx * s.dx + s.dy * s.dy + s.dz * s.dz;
  return s.r2 > 0;
}

template <bool kMixed>
bool CollisionGrid::pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) {
  if (!within_splash_ && g.splash[i] == g.splash[j] && g.splash[i] != kNoSplash) return false;
  Separation s;
  if (!overlap<kMixed>(g, i, j, s)) return false;
  double mi = m, mj = m;
  if constexpr (kMixed) mi = masses_[g.kind[i]], mj = masses_[g.kind[j]];
  Vec3 v1{g.vx[i], g.vy[i], g.vz[i]}, v2{g.vx[j], g.vy[j], g.vz[j]};
  const Vec3 u1 = v1, u2 = v2;
  if (!collide(v1, v2, mi, mj, Vec3{s.dx, s.dy, s.dz} / std::sqrt(s.r2), law)) return false;
  g.vx[i] = v1.x(), g.vy[i] = v1.y(), g.vz[i] = v1.z(), g.vx[j] = v2.x(), g.vy[j] = v2.y(), g.vz[j] = v2.z();
  if (s.back > 0) {  // swept: since the contact they have moved at their new velocities
    const std::size_t a = 3 * shift_slot(i), b = 3 * shift_slot(j);
    for (int k = 0; k < 3; ++k) {
      shift_[a + static_cast<std::size_t>(k)] += s.back * (v1[k] - u1[k]);
      shift_[b + static_cast<std::size_t>(k)] += s.back * (v2[k] - u2[k]);
    }
  }
  return true;
}

std::size_t CollisionGrid::shift_slot(std::size_t i) {
  if (slot_.size() <= i) slot_.resize(i + 1, kNone);
  if (slot_[i] == kNone) {
    slot_[i] = static_cast<std::uint32_t>(shifted_.size());
    shifted_.push_back(static_cast<std::uint32_t>(i));
    shift_.insert(shift_.end(), {0.0, 0.0, 0.0});
  }
  return slot_[i];
}

void CollisionGrid::forget_shifts() {
  for (const std::uint32_t i : shifted_) slot_[i] = kNone;
  shifted_.clear(), shift_.clear();
}

// Only the grains that collided: the others would move by zero.
void CollisionGrid::apply_shifts(Grains& g) {
  for (std::size_t n = 0; n < shifted_.size(); ++n) {
    const std::size_t i = shifted_[n];
    if (i >= g.size()) continue;  // a ghost's, gone since
    const double* const d = &shift_[3 * n];
    g.x[i] = into(g.x[i] + d[0], length_), g.y[i] = into(g.y[i] + d[1], width_);
    g.z[i] += d[2];
  }
  forget_shifts();
}

}  // namespace grainlab::ripples::hybrid
