// The ripple models behind one interface, created by name from their configs.
#include <gtest/gtest.h>

#include "input_error.hpp"
#include "ripple_model.hpp"

namespace grainlab::ripples {

TEST(RippleModel, EveryModelIsCreatedByItsTableAndRunsThroughTheInterface) {
  const std::map<std::string, std::string> configs = {
      {"bins", "[bins]\nbins = 200\nshots = 20000\nframes = 4\n"},
      {"lattice", "[lattice]\ncolumns = 400\nejections_per_grain = 4\nframes = 4\n"}};
  ASSERT_EQ(ripple_models().size(), configs.size());
  for (const RippleModelEntry& e : ripple_models()) {
    RippleModelRun r = create_ripple_model(configs.at(e.name), "c.toml");
    EXPECT_EQ(r.name, e.name);
    EXPECT_EQ(r.frames, 4);
    const std::vector<double> before = r.model->surface();
    ASSERT_GT(before.size(), 100u) << e.name;
    double mass0 = 0, mass1 = 0;
    for (double v : before) mass0 += v;
    r.model->advance(r.duration);
    EXPECT_DOUBLE_EQ(r.model->time(), r.duration) << e.name;
    for (double v : r.model->surface()) mass1 += v;
    EXPECT_NEAR(mass1, mass0, 1e-9 * mass0) << e.name;  // grains are moved, never made or lost
    EXPECT_NE(r.model->surface(), before) << e.name;
    for (const char* k : {"rms", "wavelength", "autocorrelation_wavelength", "height", "ripple_index",
                          "stoss_deg", "lee_deg"})
      EXPECT_EQ(r.model->diagnostics().count(k), 1u) << e.name << " " << k;
    EXPECT_GT(r.model->dx(), 0);
  }
}

TEST(RippleModel, AConfigWithoutAModelTableOrWithASplashButNoReaderIsRefused) {
  EXPECT_THROW(create_ripple_model("[scene]\nname = 'x'\n", "c.toml"), InputError);
  EXPECT_THROW(create_ripple_model("[lattice]\nsplash = 'sand-gun'\n", "c.toml"), InputError);
  const RippleModelRun r =
      create_ripple_model("[lattice]\nsplash = 'f.h5'\ncolumns = 400\n", "c.toml", [](const LatticeRun& run) {
        EXPECT_EQ(run.splash, "f.h5");
        return SplashHops{{10.0, -5.0}, -1, {}};
      });
  EXPECT_EQ(r.name, "lattice");
}

}  // namespace grainlab::ripples
