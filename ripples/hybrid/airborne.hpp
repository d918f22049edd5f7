#pragma once
// The airborne grains of the 3-D hybrid model (structure of arrays) and the column grid that finds their
// mid-air collisions. Shared by the flat-bed flux runs and the ripple runs (transport.hpp).
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "collision.hpp"

namespace grainlab::ripples::hybrid {

// The transport keeps them in ascending id order (ids are handed out in increasing order, removal keeps
// the order, arrivals from other MPI ranks are merged in), so that every order-dependent step (collisions,
// splashes) sees them in an order that does not depend on how the domain is split.
inline constexpr std::uint64_t kNoSplash = ~std::uint64_t{0};
struct Grains {
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::uint8_t> kind;  // size class (all 0 in a run of one size)
  std::vector<std::uint64_t> id;
  // The number of the splash that last sent the grain up (kNoSplash: none, e.g. a trigger grain). The
  // grains of one splash leave the bed with the velocities the splash function gave them, already the
  // outcome of their contacts with each other, so they do not collide with each other in the air.
  std::vector<std::uint64_t> splash;
  std::size_t size() const { return x.size(); }
  void add(double px, double py, double pz, double ux, double uy, double uz, int k = 0, std::uint64_t n = 0,
           std::uint64_t s = kNoSplash) {
    x.push_back(px), y.push_back(py), z.push_back(pz), vx.push_back(ux), vy.push_back(uy), vz.push_back(uz);
    kind.push_back(static_cast<std::uint8_t>(k)), id.push_back(n), splash.push_back(s);
  }
  // Drops every grain i < drop.size() with drop[i] set, keeping the others' order.
  void remove_marked(const std::vector<char>& drop);
  // Takes in `more` (ascending ids, none shared with these), keeping the ids ascending.
  void merge(const Grains& more);
  void truncate(std::size_t n);
};

// Grain i of g as kGrainValues numbers (id, x, y, z, vx, vy, vz, kind, splash) appended to `out`, and
// back: what crosses between MPI ranks and into checkpoints.
inline constexpr std::size_t kGrainValues = 9;
// A splash number as a double (exact below 2^53; kNoSplash as -1) and back.
inline double splash_value(std::uint64_t s) {
  return s == kNoSplash ? -1.0 : static_cast<double>(s);
}
inline std::uint64_t splash_number(double v) {
  return v < 0 ? kNoSplash : static_cast<std::uint64_t>(v);
}
void pack_grain(const Grains& g, std::size_t i, std::vector<double>& out);
void unpack_grains(const double* values, std::size_t count, Grains& into);

// x taken into [0, period) (a grain moves far less than a period per step): one number, or each lane of
// a vector of them (GCC's vector extensions, whose ?: picks lane by lane: the move loop's registers).
template <class V>
V into(V x, double period) {
  return x < V{} ? x + period : (x >= V{} + period ? x - period : x);
}

// A column index i in [-n, 2n) taken into [0, n) (periodic).
inline long wrap(long i, long n) {
  return i < 0 ? i + n : (i >= n ? i - n : i);
}
// The nearest periodic image of a separation (both grains inside the box).
inline double nearest(double s, double period) {
  return s > 0.5 * period ? s - period : (s < -0.5 * period ? s + period : s);
}

// Mid-air collisions: grains chained into vertical columns one diameter square (periodic in x and y), each
// grain checked against the grains chained before it in its column and against the four columns ahead of
// it, each pair of overlapping, approaching grains collided once per step.
//
// A grain may meet two others in one step, so the order of the pairs matters to the last bit. It is
// fixed independently of the MPI ranks: the columns in x are grouped into `blocks` (a number the run
// fixes, not the rank count; each rank holds whole blocks), and every pair within a block is collided
// first, grains in ascending id; then the pairs that straddle two blocks, in the same order. Blocks are
// at least two columns wide, so no grain is in the pairs of two block boundaries: each boundary can be
// done by whichever rank(s) see both sides, and gives the same bits. Saltation is dilute: most
// columns are empty (the bed has tens of columns per airborne grain), so the work per step touches only
// the grains' columns and a bit per column (the chain heads are never cleared), and a column holds a
// grain or two whose z test rejects most pairs.
class CollisionGrid {
 public:
  // d: the largest grain diameter; cell_x, cell_y: the columns' widths, at least d (wider when pairs are
  // swept over a step, so that two grains that meet within it are in neighbouring columns at its end).
  CollisionGrid(double length, double width, double d, double cell_x = 0, double cell_y = 0);
  // Grains of several sizes: diameter and mass per size class (Grains::kind); without, all grains are
  // equal, of diameter d and the mass collide_all is given.
  void set_sizes(std::vector<double> diameters, std::vector<double> masses);
  // The grouping of the x columns (1 <= blocks <= columns / 2, or 1).
  void set_blocks(long blocks);
  long blocks() const { return blocks_; }
  long columns_x() const { return nx_; }
  long columns_y() const { return ny_; }
  long column_x(double x) const { return std::min(nx_ - 1, static_cast<long>(x * inv_hx_)); }
  // Grain i's column, x * columns_y() + y, as the last collide_all found it (its grains, in their order).
  std::size_t column_of(std::size_t i) const {
    return static_cast<std::size_t>(column_x_[i]) * static_cast<std::size_t>(ny_) + column_y_[i];
  }
  long column_y(double y) const { return std::min(ny_ - 1, static_cast<long>(y * inv_hy_)); }
  double cell_x() const { return 1 / inv_hx_; }  // cm
  double cell_y() const { return 1 / inv_hy_; }
  long block_of(long column_x) const { return column_x * blocks_ / nx_; }
  // Swept pairs (`span` > 0): two grains collide if their straight paths over the last `span` seconds
  // (back from where they are, at their present velocities) brought them into contact, however far they
  // passed through each other; they are collided at the first contact. Since then they have moved at
  // their new velocities: the shift in position that makes is kept per grain and applied by
  // apply_shifts once every pair is done, so that the columns, and with them which pairs straddle
  // which boundary, stay as they were when the pass began, on any split of the domain. `span` 0: they
  // collide only if they overlap now (the paper's rule, for steps over which no grain moves more than a
  // fraction of a diameter). The columns must be at least d plus the largest relative travel over the
  // span wide.
  void set_sweep(double span) { sweep_ = span; }
  // Whether grains sent up by the same splash (Grains::splash) collide with each other: not by default.
  void set_collide_within_splash(bool collide) { within_splash_ = collide; }
  // Swept pairs: moves the first g.size() grains by the shifts their collisions gave them, and forgets
  // the shifts (those of ghost grains appended for collide_across and removed since).
  void apply_shifts(Grains& g);
  // Collides every overlapping, approaching pair of g's grains: those within a block, then those across
  // block boundaries; returns how many collided.
  std::uint64_t collide_all(Grains& g, double m, const CollisionLaw& law);
  // The pairs across one block boundary whose sides lie on two ranks: grains `left` of g (one x column,
  // ascending id) against grains `right` (the next x column, periodic; ascending id), in collide_all's
  // order. `count`: whether the collisions are counted (one side of each boundary counts them).
  std::uint64_t collide_across(Grains& g, const std::vector<std::uint32_t>& left,
                               const std::vector<std::uint32_t>& right, double m, const CollisionLaw& law,
                               bool count);
  // Swept pairs of g's grains listed by index (the pairs of grains too fast for the columns), collided in
  // the list's order. The shifts their collisions give are returned, three per grain of g (zero for the
  // others), and kept apart from those collide_all leaves for apply_shifts; `touched` gets each grain that
  // collided, once, in ascending index. Returns how many pairs collided.
  std::uint64_t collide_pairs(Grains& g, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                              double m, const CollisionLaw& law, std::vector<double>& shifts,
                              std::vector<std::uint32_t>& touched);

 private:
  template <bool kMixed>
  std::uint64_t collide_as(Grains& g, double m, const CollisionLaw& law);
  struct Separation {
    double dx, dy, dz, r2;  // from grain i to grain j (nearest periodic image), at contact
    double back = 0;        // swept: how long before now they touched
  };
  // Whether grains i and j overlap (swept: touched within the span) and are apart at all; `s` gets
  // their separation at contact.
  template <bool kMixed>
  [[gnu::always_inline]] inline bool overlap(const Grains& g, std::size_t i, std::size_t j,
                                             Separation& s) const;
  template <bool kMixed>
  [[gnu::always_inline]] inline bool pair(Grains& g, std::size_t i, std::size_t j, double m,
                                          const CollisionLaw& law);
  long nx_, ny_, blocks_ = 1;
  std::vector<char> edge_;  // per x column: the last of its block (its pairs ahead in x cross a boundary)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> across_;  // straddling pairs, in order, to do last
  template <bool kMixed>
  [[gnu::always_inline]] inline bool swept_contact(const Grains& g, std::size_t i, std::size_t j,
                                                   double reach, Separation& s) const;
  double inv_hx_, inv_hy_, d_, length_, width_, sweep_ = 0;
  bool within_splash_ = false;
  std::vector<double> diameters_, masses_;
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> head_;  // per occupied column: the last grain chained into it
  // One bit per column, whether it holds a grain: most grains have no neighbour in the four columns ahead,
  // and two loads of these bits say so where four chain heads, 32 times as large, would be read. The bits
  // also say which heads hold this pass's chains: head_ is never cleared.
  // Rows of ny_ + 2 bits: row ix's bit iy + 1 is column (ix, iy), and its bits 0 and ny_ + 1 repeat
  // columns ny_ - 1 and 0 (the periodic wrap in y); row nx_ repeats row 0 (the wrap in x). So the
  // columns ahead of (ix, iy) are bits iy .. iy + 2 of row ix + 1 and bit iy + 2 of row ix, whatever
  // the column. Stored as bytes, with a word of padding, so any three bits are one unaligned load.
  std::vector<std::uint8_t> occupied_;
  std::size_t bit_row_ = 0;
  // The bits as the pass works on them, by value: byte stores may alias anything, so the pass keeps this
  // copy in registers instead of reloading the grid's members after every store.
  struct Occupancy {
    std::uint8_t* bytes;
    std::size_t row;  // bits per row, ny + 2
    long nx, ny;
    std::size_t bit(long ix, long iy) const {  // the bit before column (ix, iy)'s own
      return static_cast<std::size_t>(ix) * row + static_cast<std::size_t>(iy);
    }
    void mark(long ix, long iy, bool on) const;
    std::uint64_t from(std::size_t bit) const;  // the bits from `bit` on, in the low ones of a word
    // One bit, read as a byte: a word read just after the pass's byte stores nearby cannot take its
    // value from them and waits for them to reach the cache.
    bool test(std::size_t bit) const { return bytes[bit / 8] >> (bit % 8) & 1; }
  };
  Occupancy occupancy() { return {occupied_.data(), bit_row_, nx_, ny_}; }
  std::vector<std::uint32_t> next_;                 // per grain: the grain chained before it
  std::vector<std::uint32_t> column_x_, column_y_;  // per grain: its column's x and y
  // Swept: the grains whose collisions shifted them (in the order they first collided), x y z each, and
  // per grain its place in that list (kNone: not shifted). Few grains collide in a step: a list spares
  // clearing and reading three numbers for every grain.
  std::vector<std::uint32_t> shifted_, slot_;
  std::vector<double> shift_;
  std::size_t shift_slot(std::size_t i);  // grain i's place in the list (added, with a zero shift, if new)
  void forget_shifts();
};

}  // namespace grainlab::ripples::hybrid
