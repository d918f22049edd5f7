// Haff's bin model (thesis Ch. V section 4): conservation, repose, and undulations that form and coarsen.
#include <gtest/gtest.h>

#include <cmath>

#include "bin_model.hpp"

using namespace grainlab::ripples;

TEST(BinModel, UndulationsFormAndCoarsenWithGrainsConserved) {
  BinModelParams p;
  p.bins = 400;
  BinModel m(p);
  const double grains = m.total_grains(), rough0 = m.rms_roughness();
  m.fire(100000);
  const double lambda1 = m.dominant_wavelength(), rough1 = m.rms_roughness();
  m.fire(900000);
  EXPECT_NEAR(m.total_grains(), grains, 1e-6);
  EXPECT_GT(rough1, 5 * rough0);                // a flat, slightly noisy bed roughens into undulations
  EXPECT_GE(m.dominant_wavelength(), lambda1);  // and they merge into longer ones
  EXPECT_GT(m.dominant_wavelength(), 10);       // wavelengths of many bins, not bin-to-bin noise
  // No step steeper than the angle of repose survives.
  const double max_step = std::tan(p.repose_deg * M_PI / 180) * p.bin_width + 1e-9;
  const auto& h = m.heights();
  for (std::size_t i = 0; i < h.size(); ++i) EXPECT_LE(std::abs(h[i] - h[(i + 1) % h.size()]), max_step) << i;
}

TEST(BinModel, SameSeedSameBed) {
  BinModelParams p;
  p.bins = 200;
  BinModel a(p), b(p);
  a.fire(20000), b.fire(20000);
  EXPECT_EQ(a.heights(), b.heights());
}
