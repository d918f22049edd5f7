#pragma once
// The 3-D engine's broad phase: bounding spheres binned in a uniform grid of cells at least one largest
// diameter wide, rebuilt from the positions at every force evaluation. It hands each body the bodies after
// it in index order whose cells touch its own, sorted, so a force loop over them visits the overlapping
// pairs in exactly the all-pairs order (the same sums, bit for bit) in O(N) instead of O(N^2).
#include <array>
#include <cstddef>
#include <vector>

#include "polyhedron.hpp"

namespace grainlab::dem {

class SphereCells {
 public:
  void build(const std::vector<Vec3>& centres, double max_radius);
  // The indices j > i in the 27 cells around i's, ascending. Valid until the next call.
  const std::vector<std::size_t>& after(std::size_t i);

 private:
  std::size_t cell_index(long x, long y, long z) const;
  double size_ = 1;
  Vec3 origin_ = Vec3::Zero();
  long nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<long> cell_of_;  // per body: its cell
  std::vector<std::size_t> start_,
      items_;  // counting sort: bodies of cell c are items_[start_[c] .. start_[c+1])
  std::vector<std::array<long, 3>> coords_;
  std::vector<std::size_t> near_;
};

}  // namespace grainlab::dem
