// Ch. III's impacts with spheres: a small poured bed, struck as in CASE A. The rebound and the ejecta
// cannot carry away more energy than the incident grain brought, and the ensemble (gathered as rows over
// MPI ranks) returns the same impacts as running them one by one.
#include <gtest/gtest.h>

#include <cmath>

#include "impacts3d.hpp"

namespace grainlab::validation {

namespace {

Bed3d small_bed() {
  Bed3dSpec spec;
  spec.count = 360;
  spec.width = 16, spec.depth = 12;
  return build_bed3d(spec);
}

TEST(Impacts3d, SpheresStruckAsCaseAGiveBackNoMoreEnergyThanTheyGet) {
  const Bed3d bed = small_bed();
  // 360 spheres of 4.19 cm^3 in 16 x 12 cm at packing ~0.55: about 14 cm deep.
  EXPECT_GT(bed.top, 10.0);
  EXPECT_LT(bed.top, 20.0);
  const ImpactCase& c = impact_case("A");
  ImpactOptions o;
  o.duration = 0.03;
  const std::vector<Impact3dResult> all = run_impact3d_ensemble(bed, c, 3, 2, o);
  ASSERT_EQ(all.size(), 2u);
  for (std::size_t k = 0; k < all.size(); ++k) {
    const Impact3dResult& r = all[k];
    const Impact3dResult one = run_impact3d(bed, c, 3, k, o);
    EXPECT_EQ(one.ejecta.size(), r.ejecta.size());
    EXPECT_EQ(one.rebounded, r.rebounded);
    EXPECT_EQ(one.vx, r.vx);
    EXPECT_NEAR(r.incident_mass, 2 * M_PI, 1e-12);  // the thesis disc's mass
    const Impact3dSummary s = summarize_impacts3d({r});
    // Kinetic energy out (rebound and ejecta where they left the bed) over in. The incident grain falls
    // about 1 cm after release, which releases 2e-4 of its energy.
    const double out = (r.rebounded ? std::pow(s.q.at("eps_i").mean, 2) : 0) + s.q.at("ej_energy").mean;
    EXPECT_LT(out, 1.0 + 2e-4) << "impact " << k;
    EXPECT_GT(out, 0.0);
    if (r.rebounded) {
      EXPECT_GT(r.vz, 0);
    }
  }
}

}  // namespace

}  // namespace grainlab::validation
