#pragma once
// The airborne grains of the 3-D hybrid model (structure of arrays) and the column grid that finds their
// mid-air collisions. Shared by the flat-bed flux runs and the ripple runs (transport.hpp).
#include <cstdint>
#include <vector>

#include "collision.hpp"

namespace grainlab::ripples::hybrid {

struct Grains {
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<std::uint8_t> kind;  // size class (all 0 in a run of one size)
  std::size_t size() const { return x.size(); }
  void add(double px, double py, double pz, double ux, double uy, double uz, int k = 0) {
    x.push_back(px), y.push_back(py), z.push_back(pz), vx.push_back(ux), vy.push_back(uy), vz.push_back(uz);
    kind.push_back(static_cast<std::uint8_t>(k));
  }
  void remove(std::size_t i) {  // swap with the last
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz}) (*v)[i] = v->back(), v->pop_back();
    kind[i] = kind.back(), kind.pop_back();
  }
};

// x taken into [0, period) (a grain moves far less than a period per step).
inline double into(double x, double period) {
  return x < 0 ? x + period : (x >= period ? x - period : x);
}

// Mid-air collisions: grains chained into vertical columns one diameter square (periodic in x and y), each
// grain checked against the grains chained before it in its column and against the four columns ahead of
// it, each pair of overlapping, approaching grains collided once per step. Saltation is dilute: most
// columns are empty (the bed has tens of columns per airborne grain), so the work per step touches only
// the grains' columns (the chain heads are cleared grain by grain, never column by column), and a column
// holds a grain or two whose z test rejects most pairs.
class CollisionGrid {
 public:
  // d: the largest grain diameter (the columns' width).
  CollisionGrid(double length, double width, double d);
  // Grains of several sizes: diameter and mass per size class (Grains::kind); without, all grains are
  // equal, of diameter d and the mass collide_all is given.
  void set_sizes(std::vector<double> diameters, std::vector<double> masses);
  // Collides every overlapping, approaching pair; returns how many collided.
  std::uint64_t collide_all(Grains& g, double m, const CollisionLaw& law);

 private:
  template <bool kMixed>
  std::uint64_t collide_as(Grains& g, double m, const CollisionLaw& law);
  template <bool kMixed>
  bool pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) const;
  long nx_, ny_;
  double inv_hx_, inv_hy_, d_, length_, width_;
  std::vector<double> diameters_, masses_;
  static constexpr std::uint32_t kNone = ~std::uint32_t{0};
  std::vector<std::uint32_t> head_;           // per column: the last grain chained into it, or kNone
  std::vector<std::uint32_t> next_, column_;  // per grain: the grain chained before it, its column
};

}  // namespace grainlab::ripples::hybrid
