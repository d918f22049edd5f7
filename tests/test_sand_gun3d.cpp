// The sand-gun experiment with spheres: the tables' rows as the experiment printed them, the power-law fit
// the suite's trend checks use, and a sand bed that holds still before it is shot at.
#include <gtest/gtest.h>

#include <cmath>

#include "sand_gun3d.hpp"

namespace grainlab::validation {

namespace {

TEST(SandGun3d, RowsAreTheTablesInCentimetres) {
  const auto& rows = sand_gun_rows();
  ASSERT_EQ(rows.size(), 9u);
  // Table 3.11 row 1 and Table 3.12 row 1, back from the splash file's sqrt(g d) and d units.
  EXPECT_NEAR(rows[0].speed, 650, 1e-9);
  EXPECT_NEAR(rows[0].alpha_deg, 15, 1e-12);
  EXPECT_EQ(rows[0].events, 12u);
  EXPECT_NEAR(rows[0].measured.at("theta_i"), 68, 1e-12);
  EXPECT_NEAR(rows[0].measured_sd.at("theta_i"), 13, 1e-12);
  EXPECT_NEAR(rows[0].measured.at("ejecta"), 2.8, 1e-12);
  EXPECT_NEAR(rows[0].measured.at("reptation"), 4.3, 1e-9);
  EXPECT_NEAR(rows[0].measured.at("ej_vz"), 48, 1e-9);
  // Row 8 (1200 cm/s at 10 deg): reptation per event is ejecta x reptation per particle (the OCR repair).
  EXPECT_NEAR(rows[7].speed, 1200, 1e-9);
  EXPECT_NEAR(rows[7].measured.at("reptation_event"), 4.9 * 8.7, 1e-9);
}

TEST(SandGun3d, PowerLawFitRecoversAnExponent) {
  const std::vector<double> v = {650, 760, 910, 1000, 1100, 1200};
  std::vector<double> y;
  std::vector<MeanInterval> m;
  for (double x : v) {
    y.push_back(3 * std::pow(x, 1.5));
    MeanInterval s;
    s.n = 10, s.mean = y.back(), s.lo = 0.9 * y.back(), s.hi = 1.1 * y.back();
    m.push_back(s);
  }
  EXPECT_NEAR(fit_power_law(v, y).exponent, 1.5, 1e-12);
  const PowerLaw p = fit_power_law(v, m);
  EXPECT_NEAR(p.exponent, 1.5, 1e-12);
  EXPECT_GT(p.half_width, 0);
  // The experiment's ejecta per event over its six rows at 15-16 deg. The thesis fits a line (0.67 per m/s,
  // intercept -2.0: "roughly linearly, not as v^2"); over 650-1200 cm/s that line reads as a power law of
  // exponent 1.5205 (numpy.polyfit of the logs, computed apart from this code).
  std::vector<double> ejecta, speed;
  for (const SandGunRow& r : sand_gun_rows())
    if (r.alpha_deg >= 15 && r.alpha_deg <= 16)
      speed.push_back(r.speed), ejecta.push_back(r.measured.at("ejecta"));
  ASSERT_EQ(speed.size(), 6u);
  EXPECT_NEAR(fit_power_law(speed, ejecta).exponent, 1.5205, 1e-4);
}

// The photographs' counting rule: an ejectum recorded at top + 1 d moving up at v_z rises v_z^2 / 2g more,
// so with d = 0.078 cm it is seen above top + 3 d only if v_z >= sqrt(2 g 2 d) = 17.49 cm/s.
TEST(SandGun3d, EjectaBelowTheApparentSurfaceAreNotCounted) {
  Impact3dResult r;
  r.incident_speed = 1000, r.alpha_deg = 15, r.g = 981;
  for (double vz : {10.0, 17.4, 17.6, 40.0}) {
    Ejectum3d e;
    e.vx = 5, e.vz = vz;
    r.ejecta.push_back(e);
  }
  const auto all = sand_gun_quantities({r});
  EXPECT_EQ(all.at("ejecta").mean, 4);
  EXPECT_NEAR(all.at("ej_vz").mean, (10 + 17.4 + 17.6 + 40) / 4, 1e-12);
  const auto seen = sand_gun_quantities({r}, 3, 0.078);
  EXPECT_EQ(seen.at("ejecta").mean, 2);
  EXPECT_NEAR(seen.at("ej_vz").mean, (17.6 + 40) / 2, 1e-12);
  EXPECT_NEAR(seen.at("reptation_event").mean, 2 * 5 * (17.6 + 40) / 981, 1e-12);
  EXPECT_EQ(sand_gun_quantities({r}, 1, 0.078).at("ejecta").mean, 4);  // 1 d: the thesis's rule
  // A rule above 1 d without the grains' size cannot be applied: it must not silently count everything.
  EXPECT_THROW(sand_gun_quantities({r}, 3, 0), std::invalid_argument);
  EXPECT_THROW(sand_gun_quantities({r}, 0.5, 0.078), std::invalid_argument);
}

TEST(SandGun3d, SandBedHoldsStill) {
  // A small sand bed (0.71 x 0.35 cm, ten grains deep). Left alone for an impact's 0.0138 s it must move
  // less than the thesis-sized bed's limits scaled to the grain: 2.5 % of a diameter, 1 cm/s x sqrt(r / 1
  // cm).
  const Bed3dSpec spec = sand_gun_bed_spec(400);
  const Bed3d bed = build_bed3d(spec);
  EXPECT_LT(bed.removed, 20u);
  EXPECT_EQ(bed.deep_movers, 0u);
  EXPECT_GT(bed.top, 0.5);
  const BedHold h = hold_bed3d(bed, "native", sand_gun_options(spec).duration, 1e-5);
  EXPECT_LT(h.max_displacement, 0.025 * 2 * spec.radius);
  EXPECT_LT(h.max_speed, 1.0 * spec.time_scale);
}

}  // namespace

}  // namespace grainlab::validation
