// Scene files: every mistake names file, line and key.
#include <gtest/gtest.h>

#include "scene.hpp"
#include "world.hpp"

using namespace grainlab;

namespace {

const char* kGood = R"toml([scene]
duration = 1.0
effects = ["gravity", "normal_contact"]
[materials.grain]
k_n = 1e6
restitution = 0.5
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 5.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [3.0, 5.0]
)toml";

// Replaces the first occurrence of `from` in the good scene.
std::string edit(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

InputError error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse_scene(text, "bad.toml", sets);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return InputError({}, "", "");
}

}  // namespace

TEST(Scene, GoodSceneReads) {
  const Scene s = parse_scene(kGood, "good.toml");
  EXPECT_EQ(s.bodies.size(), 2u);
  EXPECT_TRUE(s.effects.has(Effect::gravity));
  EXPECT_FALSE(s.effects.has(Effect::friction));
  EXPECT_NEAR(s.bodies[0].mass, 2 * M_PI, 1e-12);
  EXPECT_NEAR(s.bodies[0].inertia, 0.5 * 2 * M_PI, 1e-12);
}

TEST(Scene, UnknownKeyNamesFileLineAndKey) {
  const InputError e = error_of(edit("radius = 1.0\ndensity = 2.0\nposition = [3.0",
                                     "radius = 1.0\nradious = 2\ndensity = 2.0\nposition = [3.0"));
  EXPECT_EQ(e.where().file, "bad.toml");
  EXPECT_EQ(e.where().line, 13);
  EXPECT_EQ(e.key(), "bodies[1].radious");
  EXPECT_NE(std::string(e.what()).find("unknown key"), std::string::npos);
}

TEST(Scene, WrongTypeIsNamed) {
  const InputError e = error_of(edit("duration = 1.0", "duration = \"long\""));
  EXPECT_EQ(e.key(), "scene.duration");
  EXPECT_EQ(e.where().line, 2);
  EXPECT_NE(std::string(e.what()).find("expected a number, found a string"), std::string::npos);
}

TEST(Scene, NonPhysicalValuesAreRejected) {
  EXPECT_EQ(error_of(edit("radius = 1.0", "radius = -1.0")).key(), "bodies[0].radius");
  EXPECT_EQ(error_of(edit("density = 2.0", "mass = 0.0")).key(), "bodies[0].mass");
  EXPECT_EQ(error_of(edit("k_n = 1e6", "k_n = nan")).key(), "materials.grain.k_n");
  EXPECT_EQ(error_of(edit("restitution = 0.5", "restitution = 1.5")).key(), "materials.grain.restitution");
  EXPECT_EQ(error_of(edit("\"normal_contact\"]", "\"normal_contact\", \"magnetism\"]")).key(),
            "scene.effects");
}

TEST(Scene, InitialOverlapBeyondToleranceIsRejected) {
  const InputError e = error_of(edit("position = [3.0, 5.0]", "position = [1.5, 5.0]"));
  EXPECT_EQ(e.key(), "bodies[1].position");
  EXPECT_EQ(e.where().line, 11);
  EXPECT_NE(std::string(e.what()).find("overlaps body id 0"), std::string::npos);
  // Within the tolerance (1 % of the radius) is accepted.
  EXPECT_NO_THROW(parse_scene(edit("position = [3.0, 5.0]", "position = [1.995, 5.0]"), "ok.toml"));
}

TEST(Scene, MissingMaterialPairIsNamed) {
  std::string s =
      edit("[[bodies]]", "[materials.glass]\nk_n = 1e7\nrestitution = 0.9\n[[bodies]]\nmaterial = \"glass\"");
  s = s.replace(s.rfind("[[bodies]]"), 10, "[[bodies]]\nmaterial = \"grain\"");
  const InputError e = error_of(s);
  EXPECT_EQ(e.key(), "material_pairs");
  EXPECT_NE(std::string(e.what()).find("between = [\"glass\", \"grain\"]"), std::string::npos);
}

TEST(Scene, FrictionNeedsAShearSpring) {
  const InputError e = error_of(edit("\"normal_contact\"]", "\"normal_contact\", \"friction\"]"));
  EXPECT_EQ(e.key(), "materials.grain.k_s");
}

TEST(Scene, SetOverridesValuesAndReportsItsOwnMistakes) {
  const Scene s = parse_scene(kGood, "good.toml",
                              {"scene.duration=2.5", "accuracy.integrator=verlet", "bodies.1.radius=0.5"});
  EXPECT_DOUBLE_EQ(s.duration, 2.5);
  EXPECT_EQ(s.accuracy.integrator, Integrator::VelocityVerlet);
  EXPECT_DOUBLE_EQ(s.bodies[1].radius, 0.5);
  const InputError e = error_of(kGood, {"scene.duration=-1"});
  EXPECT_EQ(e.key(), "scene.duration");
  EXPECT_NE(e.where().file.find("--set scene.duration=-1"), std::string::npos);
  EXPECT_EQ(error_of(kGood, {"bodies.7.radius=1"}).key(), "bodies.7.radius");
  EXPECT_EQ(error_of(kGood, {"scene.durration=1"}).key(), "scene.durration");
  // A misspelt material makes a new, incomplete table: the error names the --set and what the scene has.
  const InputError typo = error_of(kGood, {"materials.grian.mu=0.2"});
  EXPECT_EQ(typo.key(), "materials.grian");
  EXPECT_NE(typo.where().file.find("--set materials.grian.mu=0.2"), std::string::npos);
  EXPECT_NE(std::string(typo.what()).find("beside it: grain"), std::string::npos) << typo.what();
}

TEST(Scene, TomlSyntaxErrorHasALine) {
  const InputError e = error_of("[scene]\nduration = = 1\n");
  EXPECT_EQ(e.where().line, 2);
}

TEST(Scene, PouredBedIsReproducibleFromItsSeed) {
  const char* poured = R"toml([scene]
duration = 1.0
seed = 42
effects = ["gravity", "normal_contact"]
[accuracy]
integrator = "verlet"
[materials.grain]
k_n = 1e6
restitution = 0.3
[[walls]]
from = [0.0, 0.0]
to = [20.0, 0.0]
[[walls]]
from = [0.0, 30.0]
to = [0.0, 0.0]
[[walls]]
from = [20.0, 0.0]
to = [20.0, 30.0]
[[assemblies]]
type = "poured"
count = 40
width = 20.0
origin = [0.0, 0.0]
density = 2.0
settle_time = 0.5
[assemblies.radius_distribution]
kind = "uniform"
min = 0.6
max = 1.0
)toml";
  dem::World a(parse_scene(poured, "p.toml")), b(parse_scene(poured, "p.toml"));
  dem::World c(parse_scene(poured, "p.toml", {"scene.seed=43"}));
  ASSERT_EQ(a.particles().size(), 40u);
  double top = 0;
  for (std::size_t i = 0; i < 40; ++i) {
    EXPECT_EQ(a.particles().x[i], b.particles().x[i]);
    top = std::max(top, a.particles().y[i] + a.particles().r[i]);
  }
  EXPECT_NE(a.particles().r[0] + a.particles().r[1], c.particles().r[0] + c.particles().r[1]);
  EXPECT_LT(top, 12.0);  // settled into a bed a few grains deep, not left where it was dropped
  EXPECT_LT(a.energies().kinetic(), 1.0);
}

TEST(Scene, ImpulseEngineKnobsAreReadAndChecked) {
  const std::string base = "[scene]\nduration = 1.0\neffects = [\"gravity\"]\n[accuracy]\n";
  const Scene s = parse_scene(base + "erp = 0.4\ncfm = 1e-6\nsplit_impulse = false\n", "t.toml");
  ASSERT_TRUE(s.accuracy.erp && s.accuracy.cfm);
  EXPECT_EQ(*s.accuracy.erp, 0.4);
  EXPECT_EQ(*s.accuracy.cfm, 1e-6);
  EXPECT_FALSE(s.accuracy.split_impulse);
  EXPECT_THROW(parse_scene(base + "erp = 1.5\n", "t.toml"), InputError);
  EXPECT_THROW(parse_scene(base + "cfm = -1.0\n", "t.toml"), InputError);
}
