#pragma once
// The airborne grains of the 3-D hybrid model (structure of arrays) and the column grid that finds their
// mid-air collisions. Shared by the flat-bed flux runs and the ripple runs (transport.hpp).
#include <cstdint>
#include <vector>

#include "collision.hpp"

namespace grainlab::ripples::hybrid {

struct Grains {
  std::vector<double> x, y, z, vx, vy, vz;
  std::size_t size() const { return x.size(); }
  void add(double px, double py, double pz, double ux, double uy, double uz) {
    x.push_back(px), y.push_back(py), z.push_back(pz), vx.push_back(ux), vy.push_back(uy), vz.push_back(uz);
  }
  void remove(std::size_t i) {  // swap with the last
    for (auto* v : {&x, &y, &z, &vx, &vy, &vz}) (*v)[i] = v->back(), v->pop_back();
  }
};

// x taken into [0, period) (a grain moves far less than a period per step).
inline double into(double x, double period) {
  return x < 0 ? x + period : (x >= period ? x - period : x);
}

// Mid-air collisions: grains sorted into vertical columns one diameter square (periodic in x and y; a
// counting sort, so the cost is linear), each grain checked against the rest of its column and the four
// columns ahead of it, each pair of overlapping, approaching grains collided once per step. Saltation is
// dilute, so a column holds a grain or two and the z test rejects most of them.
class CollisionGrid {
 public:
  CollisionGrid(double length, double width, double d);
  // Collides every overlapping, approaching pair of equal grains of mass m; returns how many collided.
  std::uint64_t collide_all(Grains& g, double m, const CollisionLaw& law);

 private:
  bool pair(Grains& g, std::size_t i, std::size_t j, double m, const CollisionLaw& law) const;
  long nx_, ny_;
  double inv_hx_, inv_hy_, d_, length_, width_;
  std::vector<std::uint32_t> start_, fill_, column_, order_;
};

}  // namespace grainlab::ripples::hybrid
