#pragma once
// Haff's bin model (thesis Ch. V section 4): a 2-D bed in bins; a grain fired at a fixed angle from a
// random point hits where its straight path first meets the surface (so lee slopes are shadowed); one grain
// moves from the hit bin a fixed distance downstream; after each shot, slopes steeper than the angle of
// repose are relaxed. Heights are in grain diameters; a grain changes a bin's height by 1 / bin_width.
#include <cstdint>
#include <vector>

namespace grainlab::ripples {

struct BinModelParams {
  int bins = 1000;         // periodic domain
  double bin_width = 4;    // grain diameters per bin
  double depth = 20;       // initial bed height, grain diameters
  double roughness = 0.5;  // initial random height noise (grains per bin, uniform 0..this x 2)
  double impact_deg = 10;  // shot angle below the horizontal
  int hop_bins = 3;        // reptation distance, bins
  double repose_deg = 30;  // angle of repose
  std::uint64_t seed = 1;
};

class BinModel {
 public:
  explicit BinModel(const BinModelParams& p);
  // Fires `shots` grains.
  void fire(long shots);
  const std::vector<double>& heights() const { return h_; }
  double total_grains() const;
  double rms_roughness() const;  // sd of the heights
  // The wavelength (in bins) of the highest peak of the power spectrum.
  double dominant_wavelength() const;
  long shots_fired() const { return shots_; }

 private:
  int hit_bin(int entry);
  void relax(int around);
  BinModelParams p_;
  std::vector<double> h_;
  std::uint64_t rng_state_;
  long shots_ = 0;
  double unit_;  // height of one grain in a bin
};

}  // namespace grainlab::ripples
