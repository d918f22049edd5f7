#pragma once
// The 3-D engine's broad phase: a Verlet list. Bounding spheres are binned in a grid of cells one largest
// diameter plus a skin wide; each body keeps the later bodies (in index order) within that reach, sorted.
// A force loop over them visits the overlapping pairs in exactly the all-pairs order (the same sums, bit
// for bit) in O(N). The lists stay valid until some body has moved half the skin since they were built.
#include <array>
#include <cstddef>
#include <vector>

#include "polyhedron.hpp"

namespace grainlab::dem {

class SphereCells {
 public:
  // Builds the lists for bodies at `centres` whose bounding radii are at most `max_radius`.
  void build(const std::vector<Vec3>& centres, double max_radius, double skin = 0);
  // True if the lists must be rebuilt for these positions (never built, another count, or a body moved
  // more than half the skin).
  bool stale(const std::vector<Vec3>& centres) const;
  // The indices j > i within reach of i, ascending.
  const std::size_t* begin(std::size_t i) const { return list_.data() + offset_[i]; }
  const std::size_t* end(std::size_t i) const { return list_.data() + offset_[i + 1]; }
  std::size_t builds() const { return builds_; }

 private:
  std::size_t cell_index(long x, long y, long z) const;
  double size_ = 1, skin_ = 0, reach_ = 0;
  Vec3 origin_ = Vec3::Zero();
  long nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<Vec3> built_at_;
  std::vector<std::size_t> start_, items_, offset_, list_;
  std::vector<std::array<long, 3>> coords_;
  std::size_t builds_ = 0;
};

}  // namespace grainlab::dem
