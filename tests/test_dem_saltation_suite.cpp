// What grainlab claims for the wind coupling of DEM saltation must hold in any window of any run, steady
// or not: the wind loses what the grains gain by drag (to 1 %), and the stress partition closes (fluid
// plus grain-borne stress one diameter above the bed is rho u*^2). Two short runs on a narrow bed, at two
// u* and two stiffnesses. The suite (`validate --suite dem-saltation`) asserts the same in steady state
// beside the literature checks; docs/saltation.md gives the measured numbers.
#include <gtest/gtest.h>

#include "dem_saltation.hpp"

namespace grainlab::validation {

TEST(DemSaltation, WindAndGrainsExchangeTheSameMomentum) {
  for (const auto& [u_star, k_n] : {std::pair{35.0, 2e5}, std::pair{50.0, 4e5}}) {
    DemSaltationOptions o;
    o.u_star = u_star, o.k_n = k_n;
    o.columns = 100, o.layers = 8, o.duration = 0.4, o.average_from = 0.2;
    o.model_comparison = false;
    const DemSaltationResult r = run_dem_saltation(o);
    EXPECT_NEAR(r.grain_momentum_gain / r.wind_momentum_loss, 1.0, 0.01) << "u* = " << u_star;
    EXPECT_NEAR(r.stress_partition, 1.0, 0.01) << "u* = " << u_star;
    EXPECT_GT(r.mass_flux.mean, 0) << "u* = " << u_star;
  }
}

}  // namespace grainlab::validation
