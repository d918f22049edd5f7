#include "height_field.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlab::ripples::hybrid {

namespace {
// A grain can roll or be taken over at most this many sub-regions (a guard; slopes stop it long before).
constexpr int kMaxMoves = 64;
}  // namespace

HeightField::HeightField(const HeightFieldParams& p) : p_(p) {
  if (!(p.cell > 0) || !(p.length >= 3 * p.cell) || !(p.width >= 3 * p.cell) || !(p.packing > 0) ||
      !(p.packing <= 1) || !(p.repose_deg > 0) || !(p.repose_deg < 90) || !(p.erodible >= 0))
    throw std::invalid_argument(
        "height field: cell > 0, at least 3 cells each way, 0 < packing <= 1, "
        "0 < repose < 90 deg, erodible >= 0");
  nx_ = static_cast<std::size_t>(std::lround(p.length / p.cell));
  ny_ = static_cast<std::size_t>(std::lround(p.width / p.cell));
  cell_ = p.length / static_cast<double>(nx_);  // exactly periodic in x; y spacing taken equal
  inv_cell_ = 1 / cell_;
  step_ = M_PI / 6 * p.diameter * p.diameter * p.diameter / (p.packing * cell_ * cell_);
  slope_drop_ = std::tan(p.repose_deg * M_PI / 180) * cell_;
  h_.assign(nx_ * ny_, 0.0);
  tiles_x_ = (nx_ + kTile - 1) / kTile, tiles_y_ = (ny_ + kTile - 1) / kTile;
  tile_top_.assign(tiles_x_ * tiles_y_, 0.0);
}

void HeightField::raise(std::size_t k) {
  const double h = h_[k];
  top_ = std::max(top_, h);
  const std::size_t i = k % nx_, j = k / nx_;
  // Corner of the cells i - 1 and i along x (periodic), j - 1 and j along y.
  const std::size_t tx[2] = {i / kTile, (i == 0 ? nx_ - 1 : i - 1) / kTile};
  const std::size_t ty[2] = {j / kTile, (j == 0 ? ny_ - 1 : j - 1) / kTile};
  for (std::size_t b : ty)
    for (std::size_t a : tx) {
      double& t = tile_top_[b * tiles_x_ + a];
      t = std::max(t, h);
    }
}

void HeightField::refresh_tiles() {
  std::fill(tile_top_.begin(), tile_top_.end(), -1e300);
  for (std::size_t k = 0; k < h_.size(); ++k) raise(k);
}

std::size_t HeightField::nearest(double x, double y) const {
  auto index = [&](double s, std::size_t n) {
    const long k = std::lround(s * inv_cell_) % static_cast<long>(n);
    return static_cast<std::size_t>(k < 0 ? k + static_cast<long>(n) : k);
  };
  return index(y, ny_) * nx_ + index(x, nx_);
}

std::size_t HeightField::neighbour(std::size_t k, int which) const {
  const std::size_t i = k % nx_, j = k / nx_;
  switch (which) {
    case 0:
      return j * nx_ + (i == 0 ? nx_ - 1 : i - 1);
    case 1:
      return j * nx_ + (i + 1 == nx_ ? 0 : i + 1);
    case 2:
      return (j == 0 ? ny_ - 1 : j - 1) * nx_ + i;
    default:
      return (j + 1 == ny_ ? 0 : j + 1) * nx_ + i;
  }
}

bool HeightField::share(double x, double y, double dh) {
  const Cell c = cell_at(x, y);
  const double w[4] = {(1 - c.fx) * (1 - c.fy), c.fx * (1 - c.fy), (1 - c.fx) * c.fy, c.fx * c.fy};
  for (int q = 0; q < 4; ++q)
    if (h_[c.k[q]] + dh * w[q] < -p_.erodible) return false;
  for (int q = 0; q < 4; ++q) h_[c.k[q]] += dh * w[q], raise(c.k[q]);
  sum_ += dh;
  return true;
}

BedPoint HeightField::at(double x, double y) const {
  const Corner c = corner(x, y);
  const bool lower = c.fx + c.fy <= 1;  // the triangle (00, 10, 01) or (11, 01, 10)
  const double gx = (lower ? c.h10 - c.h00 : c.h11 - c.h01) * inv_cell_;
  const double gy = (lower ? c.h01 - c.h00 : c.h11 - c.h10) * inv_cell_;
  const double norm = 1 / std::sqrt(1 + gx * gx + gy * gy);
  return {height(x, y), -gx * norm, -gy * norm, norm};
}

// Where a grain worth dh of height settles (sign +1) or is taken (sign -1): from the nearest key point, on
// to the neighbour lying furthest below it (settling) or above it (taking) while the step to that
// neighbour, once the grain is settled or taken here, would pass repose.
std::size_t HeightField::repose_walk(double x, double y, double sign, double dh, std::int64_t& moves) const {
  std::size_t k = nearest(x, y);
  for (int move = 0; move < kMaxMoves; ++move) {
    std::size_t next = k;
    double drop = 0;
    for (int w = 0; w < 4; ++w) {
      const std::size_t q = neighbour(k, w);
      if (sign * (h_[k] - h_[q]) > drop) next = q, drop = sign * (h_[k] - h_[q]);
    }
    if (next == k || drop + dh <= slope_drop_) break;
    k = next, ++moves;
  }
  return k;
}

void HeightField::set_mixture(const std::vector<double>& sizes, const std::vector<double>& fractions,
                              double psi0) {
  if (sizes.size() != fractions.size()) throw std::invalid_argument("one fraction per size class");
  volumes_.clear();
  for (double s : sizes) {
    if (!(s > 0) || !std::isfinite(s)) throw std::invalid_argument("every size class needs a positive size");
    volumes_.push_back(s * s * s);
  }
  layer_.emplace(h_.size(), fractions, psi0);
}

void HeightField::deposit(double x, double y, int kind) {
  std::int64_t moves = 0;
  const double dh = step_ * volumes_[static_cast<std::size_t>(kind)];
  const std::size_t k = repose_walk(x, y, 1, dh, moves);
  ++deposited, rolled += moves;
  if (layer_) layer_->add(k, kind, dh);
  if (p_.bilinear && moves == 0) {
    share(x, y, dh);  // settling never meets the floor
    return;
  }
  h_[k] += dh, sum_ += dh;
  raise(k);
}

bool HeightField::erode(double x, double y, int kind) {
  std::int64_t moves = 0;
  const double dh = step_ * volumes_[static_cast<std::size_t>(kind)];
  const std::size_t k = repose_walk(x, y, -1, dh, moves);
  if (p_.bilinear && moves == 0) {
    if (!share(x, y, -dh)) return false;
  } else {
    if (h_[k] - dh < -p_.erodible) return false;
    h_[k] -= dh, sum_ -= dh;
  }
  if (layer_) layer_->take(k, kind, dh);
  ++eroded, pit_taken += moves;
  return true;
}

void HeightField::restore(const std::vector<double>& heights, const std::array<std::int64_t, 4>& counters,
                          double sum, double top) {
  if (heights.size() != h_.size()) throw std::invalid_argument("the checkpoint's bed has another size");
  h_ = heights, sum_ = sum;
  refresh_tiles();
  top_ = top;  // (the checkpoint's bound, which the tiles' may undercut: either holds)
  deposited = counters[0], eroded = counters[1], rolled = counters[2], pit_taken = counters[3];
}

void HeightField::refresh() {
  refresh_tiles();
  top_ = *std::max_element(h_.begin(), h_.end());
  sum_ = 0;
  for (double v : h_) sum_ += v;
}

}  // namespace grainlab::ripples::hybrid
