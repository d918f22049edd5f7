#pragma once
// The polydisperse surface of the hybrid model's bed (Huo et al. 2021, section 2.4 and Fig. 3). Each key
// point's sub-region keeps, per size class, the volume of that class in a well-mixed "affectable" layer
// under its surface, written as bed height (volume / (phi_b cell^2), cm); the layer's depth psi is their
// sum and never less than psi0. Deposition resizes the layer (psi grows). Erosion resizes it first, down
// to psi0; past psi0 the layer shifts down and sand of the initial mix from below fills it again. Only
// composition lives here: the surface's height is the height field's.
#include <cstddef>
#include <vector>

namespace grainlab::ripples::hybrid {

// How far a mixture's fractions may sum from 1 (configs and options check it; the layer normalises them).
constexpr double kFractionTolerance = 1e-6;

class SurfaceLayer {
 public:
  // `fractions`: the initial mix by volume, one per class, positive, summing to 1 within
  // kFractionTolerance (throws std::invalid_argument otherwise; kept normalised); psi0 > 0 in cm.
  SurfaceLayer(std::size_t points, std::vector<double> fractions, double psi0);
  std::size_t kinds() const { return f0_.size(); }
  std::size_t points() const { return a_.size() / f0_.size(); }
  double psi0() const { return psi0_; }
  const std::vector<double>& initial_fractions() const { return f0_; }
  // The class of a grain drawn from point k's layer by volume, u uniform in [0, 1).
  int draw(std::size_t k, double u) const;
  // A grain of class `kind` worth dh of bed height settles at k / is taken from k. A class the layer
  // lacks is reached by deepening the layer into the initial mix below it.
  void add(std::size_t k, int kind, double dh);
  void take(std::size_t k, int kind, double dh);
  double depth(std::size_t k) const;  // psi, cm
  double amount(std::size_t k, int kind) const { return a_[k * kinds() + kind]; }
  double fraction(std::size_t k, int kind) const { return amount(k, kind) / depth(k); }
  // Volume-weighted mean of `sizes` (one per class) in point k's layer.
  double mean_size(std::size_t k, const std::vector<double>& sizes) const;
  // The amounts, point by point (kinds() per point), for checkpoints; restore throws
  // std::invalid_argument for another size or a negative amount.
  const std::vector<double>& amounts() const { return a_; }
  void restore(const std::vector<double>& amounts);

 private:
  void mix_in(std::size_t k, double depth);  // `depth` of the initial mix joins the layer from below
  std::vector<double> f0_;
  double psi0_;
  std::vector<double> a_;
};

}  // namespace grainlab::ripples::hybrid
