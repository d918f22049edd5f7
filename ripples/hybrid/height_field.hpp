#pragma once
// The hybrid model's bed (Huo et al. 2021, section 2.4): key points on a square grid, periodic in x and y,
// each owning the square sub-region around it; the surface between them is triangulated (each grid cell
// cut along its diagonal), so a grain's height above the bed and the bed's normal come from the triangle
// beneath it. A grain that settles raises its sub-region by V / (phi_b A), one that leaves lowers it.
// The angle of repose: a settling grain rolls on to the lowest neighbour while settling where it fell
// would make a slope steeper than repose toward it; a grain taken from a steep pit comes from the highest
// neighbour instead. (The paper states the rule only in words; this reading keeps every slope between
// neighbours within repose plus one grain's step, docs/hybrid.md.)
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "surface_layer.hpp"

namespace grainlab::ripples::hybrid {

struct HeightFieldParams {
  double length = 100, width = 5;  // cm, periodic
  double cell = 0.05;              // key-point spacing, cm
  double diameter = 0.025;         // cm
  double packing = 0.6;            // phi_b
  double repose_deg = 30;
  double erodible = 2;  // depth of sand below the initial surface, cm
  // Where a grain that does not roll settles or is taken: all at the nearest key point (false), or
  // shared among the four key points around it by bilinear weights (true: a smoother bed, the grain's
  // volume placed where it fell rather than moved up to half a cell).
  bool bilinear = false;
};

struct BedPoint {
  double h;           // surface height, cm
  double nx, ny, nz;  // unit normal of the triangle beneath
};

class HeightField {
 public:
  explicit HeightField(const HeightFieldParams& p);
  std::size_t nx() const { return nx_; }
  std::size_t ny() const { return ny_; }
  double cell() const { return cell_; }
  double step() const { return step_; }  // height change per grain, cm
  // Heights of the key points, x fastest (index j * nx + i is the point at (i cell, j cell)).
  const std::vector<double>& heights() const { return h_; }
  std::vector<double>& heights() { return h_; }  // (then refresh(): the bounds below follow the heights)
  // The surface at (x, y), inside the box: its height alone (cheap), or with the normal.
  double height(double x, double y) const;
  BedPoint at(double x, double y) const;
  // Asks the cache for the rows of key points around (x, y), changing nothing: callers that visit
  // places in no order (grains by id) fetch a few ahead on a bed larger than the cache.
  void prefetch(double x, double y) const;
  // A grain settles at (x, y) / leaves from (x, y); erode returns false (and changes nothing) where the
  // erodible layer is used up. `kind` is its size class (0 on a bed of one size).
  void deposit(double x, double y, int kind = 0);
  bool erode(double x, double y, int kind = 0);
  // A bed of several sizes: `sizes` in diameters (one per class), their initial `fractions` by volume, the
  // surface layer's least depth psi0 (cm). A grain of class c moves the surface sizes[c]^3 times a
  // grain of one diameter. Throws std::invalid_argument for sizes that are not positive.
  void set_mixture(const std::vector<double>& sizes, const std::vector<double>& fractions, double psi0);
  // The surface's composition (null on a bed of one size), and the class of the grain an impact at (x, y)
  // meets, drawn by volume from the layer there with u in [0, 1).
  const SurfaceLayer* layer() const { return layer_ ? &*layer_ : nullptr; }
  SurfaceLayer* layer() { return layer_ ? &*layer_ : nullptr; }
  int surface_kind(double x, double y, double u) const { return layer_ ? layer_->draw(nearest(x, y), u) : 0; }
  double mean() const { return sum_ / static_cast<double>(h_.size()); }
  // An upper bound of the highest key point (exact after refresh()).
  double top() const { return top_; }
  // An upper bound of the surface anywhere in the tile of kTile x kTile cells that holds (x, y) (inside
  // the box), kept as top() is: raised as grains settle, exact after refresh(). Most grains near a
  // rippled bed are below its highest crest but above their own tile's: one load from a table that
  // stays in cache tells them apart, where height() reads the bed all over memory.
  double tile_top(double x, double y) const;
  static constexpr std::size_t kTile = 8;
  void refresh();
  // Sets every height and the counters (a checkpoint's); throws std::invalid_argument for a wrong size.
  void restore(const std::vector<double>& heights, const std::array<std::int64_t, 4>& counters, double sum,
               double top);
  double sum() const { return sum_; }
  // Grains settled and taken since the start, and how many of each moved to a neighbour by the repose
  // rule.
  std::int64_t deposited = 0, eroded = 0, rolled = 0, pit_taken = 0;

  // The grid cell holding (x, y): its grid indices and the position in it (x and y inside the periodic box,
  // so no division).
  struct Place {
    std::size_t i0, j0;
    double fx, fy;
  };
  Place place(double x, double y) const;

 private:
  struct Corner {
    double h00, h10, h01, h11, fx, fy;
  };
  struct Cell {
    std::size_t k[4];  // key points 00, 10, 01, 11
    double fx, fy;
  };
  Cell cell_at(double x, double y) const;
  Corner corner(double x, double y) const;
  // Adds dh x (bilinear weight) to the four key points around (x, y); false (nothing changed) if one of
  // them would go below the erodible layer.
  bool share(double x, double y, double dh);
  std::size_t nearest(double x, double y) const;
  std::size_t repose_walk(double x, double y, double sign, double dh, std::int64_t& moves) const;
  std::size_t neighbour(std::size_t k, int which) const;  // 0..3: -x, +x, -y, +y
  // Key point k now stands at h: raises the bounds of the (up to four) tiles whose cells it is a corner
  // of, and top().
  void raise(std::size_t k);
  void refresh_tiles();
  HeightFieldParams p_;
  std::size_t nx_, ny_;
  double cell_, inv_cell_, step_, slope_drop_, sum_ = 0, top_ = 0;
  std::vector<double> h_;
  // Per tile (x fastest), the highest key point among its cells' corners (one past its edge each way).
  std::size_t tiles_x_ = 0, tiles_y_ = 0;
  std::vector<double> tile_top_;
  std::optional<SurfaceLayer> layer_;
  std::vector<double> volumes_{1.0};  // per size class, in grains of one diameter
};

// Inline: every airborne grain asks for the bed beneath it every step (the wind column stands on it).
// The grid cell holding (x, y) and the position in it (x and y inside the periodic box, so no division).
inline HeightField::Place HeightField::place(double x, double y) const {
  const double sx = x * inv_cell_, sy = y * inv_cell_;
  auto i0 = static_cast<std::size_t>(sx), j0 = static_cast<std::size_t>(sy);
  const double fx = sx - static_cast<double>(i0), fy = sy - static_cast<double>(j0);
  if (i0 >= nx_) i0 -= nx_;
  if (j0 >= ny_) j0 -= ny_;
  return {i0, j0, fx, fy};
}

inline HeightField::Cell HeightField::cell_at(double x, double y) const {
  const auto [i0, j0, fx, fy] = place(x, y);
  const std::size_t i1 = i0 + 1 == nx_ ? 0 : i0 + 1, j1 = j0 + 1 == ny_ ? 0 : j0 + 1;
  return {{j0 * nx_ + i0, j0 * nx_ + i1, j1 * nx_ + i0, j1 * nx_ + i1}, fx, fy};
}

inline HeightField::Corner HeightField::corner(double x, double y) const {
  const Cell c = cell_at(x, y);
  return {h_[c.k[0]], h_[c.k[1]], h_[c.k[2]], h_[c.k[3]], c.fx, c.fy};
}

inline void HeightField::prefetch(double x, double y) const {
  const Cell c = cell_at(x, y);
  __builtin_prefetch(&h_[c.k[0]]);
  __builtin_prefetch(&h_[c.k[2]]);
}

inline double HeightField::tile_top(double x, double y) const {
  const Place p = place(x, y);
  return tile_top_[p.j0 / kTile * tiles_x_ + p.i0 / kTile];
}

inline double HeightField::height(double x, double y) const {
  const Corner c = corner(x, y);
  return c.fx + c.fy <= 1 ? c.h00 + (c.h10 - c.h00) * c.fx + (c.h01 - c.h00) * c.fy
                          : c.h11 - (c.h11 - c.h01) * (1 - c.fx) - (c.h11 - c.h10) * (1 - c.fy);
}

}  // namespace grainlab::ripples::hybrid
