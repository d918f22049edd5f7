// Ripple configs get the scene reader's strictness: file, line and key in every error; the fuzz test
// mutates a valid config and every mutant is read or refused with an InputError, never a crash.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "hybrid_config.hpp"
#include "hybrid_splash_file.hpp"
#include "input_error.hpp"
#include "lammel_splash.hpp"
#include "ripple_config.hpp"

using namespace grainlab::ripples;
using grainlab::InputError;

namespace {
const std::string kGood =
    "[bins]\nbins = 100\nbin_width = 4.0\nhop_bins = 3\nimpact_angle = 10.0\nshots = 1000\n";

std::string error_of(const std::string& text) {
  try {
    parse_bin_model_config(text, "r.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

// One to three random edits of `text`: a character replaced, a few deleted, or one inserted.
static std::string mutate(std::string text, std::mt19937_64& rng, const std::string& alphabet) {
  for (int e = 0; e < 1 + static_cast<int>(rng() % 3); ++e) {
    const std::size_t at = rng() % text.size();
    switch (rng() % 3) {
      case 0:
        text[at] = alphabet[rng() % alphabet.size()];
        break;
      case 1:
        text.erase(at, 1 + rng() % 4);
        break;
      default:
        text.insert(at, 1, alphabet[rng() % alphabet.size()]);
    }
  }
  return text;
}

TEST(RippleConfig, ReadsAGoodConfig) {
  const BinModelRun r = parse_bin_model_config(kGood, "r.toml");
  EXPECT_EQ(r.params.bins, 100);
  EXPECT_EQ(r.params.hop_bins, 3);
  EXPECT_EQ(r.shots, 1000);
  EXPECT_EQ(r.params.repose_deg, 30);  // default
}

TEST(RippleConfig, MistakesNameFileLineAndKey) {
  EXPECT_NE(error_of("[bins]\nbinz = 3\n").find("r.toml:2"), std::string::npos);
  EXPECT_NE(error_of("[bins]\nbinz = 3\n").find("bins.binz"), std::string::npos);
  EXPECT_NE(error_of("[bins]\nimpact_angle = 95.0\n").find("impact_angle"), std::string::npos);
  EXPECT_NE(error_of("[bins]\nbins = \"many\"\n").find("bins.bins"), std::string::npos);
  EXPECT_NE(error_of("[bins]\nbins = 20\nhop_bins = 30\n").find("hop_bins"), std::string::npos);
  EXPECT_NE(error_of("[model]\nx = 1\n").find("[bins]"), std::string::npos);
  EXPECT_NE(error_of("[bins\n").find("r.toml:1"), std::string::npos);
}

TEST(RippleConfig, RandomMutationsAreReadOrRefusedNeverCrash) {
  std::mt19937_64 rng(2026);
  const std::string alphabet = "0123456789.-+e[]=\"\n #abinz";
  int refused = 0;
  for (int k = 0; k < 500; ++k) {
    const std::string s = mutate(kGood, rng, alphabet);
    try {
      const BinModelRun r = parse_bin_model_config(s, "m.toml");
      EXPECT_GE(r.params.bins, 16);
      EXPECT_LT(r.params.hop_bins, r.params.bins);
    } catch (const InputError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("m.toml"), std::string::npos);
    }
  }
  EXPECT_GT(refused, 0);
}

namespace grainlab::ripples {

// Mutants of a shipped config are read (and then `check` their values) or refused naming the file.
template <typename Parse, typename Check>
void fuzz_shipped_config(const std::string& name, Parse parse, Check check, std::uint64_t seed) {
  std::ifstream in(std::string(GRAINLAB_SOURCE_DIR) + "/scenes/ripples/" + name);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string good = ss.str();
  ASSERT_FALSE(good.empty()) << name;
  check(parse(good, "l.toml"));
  std::mt19937_64 rng(seed);
  const std::string alphabet = "0123456789.-+e[]=\"\n #latcewormsbrik";
  int refused = 0;
  for (int k = 0; k < 500; ++k) {
    const std::string s = mutate(good, rng, alphabet);
    try {
      check(parse(s, "l.toml"));
    } catch (const InputError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("l.toml"), std::string::npos);
    }
  }
  EXPECT_GT(refused, 0) << name;
}

TEST(RippleConfig, EveryShippedLatticePresetReads) {
  int read = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(GRAINLAB_SOURCE_DIR) + "/scenes/ripples")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("lattice_", 0) != 0 || e.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(read_lattice_config(e.path().string())) << name;
    ++read;
  }
  EXPECT_GE(read, 8);
}

TEST(RippleConfig, ShippedConfigMutationsAreReadOrRefusedNeverCrash) {
  fuzz_shipped_config(
      "lattice_fig5_22.toml", parse_lattice_config,
      [](const LatticeRun& r) {
        EXPECT_EQ(r.params.columns % 2, 0);
        EXPECT_LT(2 * std::max(r.params.forward, r.params.backward), r.params.columns);
      },
      2027);
  // The seeded start: whatever the reader lets through, the model can build (the sine's steepness, its
  // wavelength and the rough start are the reader's to refuse).
  fuzz_shipped_config(
      "lattice_seeded_sine.toml", parse_lattice_config,
      [](const LatticeRun& r) {
        if (r.params.columns <= 100000) {
          EXPECT_NO_THROW(LatticeModel{r.params});
        }
      },
      2030);
  fuzz_shipped_config(
      "worms.toml", parse_worm_ring_config,
      [](const WormRingRun& r) {
        EXPECT_GE(r.worms, 2);
        EXPECT_GT(r.A, 0);
        EXPECT_LE(r.A, 1);
      },
      2028);
  fuzz_shipped_config(
      "triangles.toml", parse_triangle_config,
      [](const TriangleRun& r) {
        EXPECT_GT(r.ratio, 0);
        EXPECT_LT(r.ratio, 1);
        EXPECT_TRUE(r.params.law == "target" || r.params.law == "brink");
      },
      2029);
}

}  // namespace grainlab::ripples

namespace grainlab::ripples::hybrid {

TEST(HybridConfig, ReadsThePresetAndNamesMistakes) {
  const std::string good = "[hybrid]\nu_star = 35\nlength = 300\nwidth = 12\ncell = 2\nduration = 500\n";
  const HybridConfig c = parse_hybrid_config(good, "h.toml");
  EXPECT_EQ(c.options.u_star, 35);
  EXPECT_EQ(c.options.length, 300);
  EXPECT_TRUE(c.options.wind_loosened);     // the paper's default
  EXPECT_TRUE(c.options.wind_follows_bed);  // grainlab's default over an erodible bed (docs/hybrid.md)
  EXPECT_FALSE(parse_hybrid_config(good + "wind_follows_bed = false\n", "h.toml").options.wind_follows_bed);
  auto error_of = [](const std::string& text) {
    try {
      parse_hybrid_config(text, "h.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error_of("[hybrid]\nustar = 3\n").find("ustar"), std::string::npos);
  EXPECT_NE(error_of("[hybrid]\nu_star = -3\n").find("h.toml:2"), std::string::npos);
  EXPECT_NE(error_of("[hybrid]\nsplash = \"x\"\n").find("splash"), std::string::npos);
  for (const std::string& set : LammelParameters::names())  // every named set, none a file
    EXPECT_EQ(parse_hybrid_config(good + "splash = \"" + set + "\"\n", "h.toml").options.splash, set);
  EXPECT_NE(error_of("[hybrid]\nejecta_launch = \"up\"\n").find("ejecta_launch"), std::string::npos);
  EXPECT_NE(error_of("[hybrid]\nsplash_frame = \"slope\"\n").find("splash_frame"), std::string::npos);
  EXPECT_FALSE(c.options.splash_level);  // the paper's frame: the bed triangle hit
  EXPECT_TRUE(parse_hybrid_config(good + "splash_frame = \"level\"\n", "h.toml").options.splash_level);
  EXPECT_NE(error_of("[hybrid]\nwind_follows_bed = 1\n").find("wind_follows_bed"), std::string::npos);
  EXPECT_FALSE(c.options.collide_within_splash);  // a splash's grains do not collide with each other
  EXPECT_TRUE(
      parse_hybrid_config(good + "collide_within_splash = true\n", "h.toml").options.collide_within_splash);
  EXPECT_NE(error_of("[hybrid]\ncollide_within_splash = 1\n").find("collide_within_splash"),
            std::string::npos);
  EXPECT_NE(error_of("[hybrid]\nwidth = 5\ncell = 2\n").find("cell"), std::string::npos);
  EXPECT_NE(error_of("[hybrid]\ntravel = 1.5\n").find("travel"), std::string::npos);  // needs swept
  EXPECT_NE(error_of("[hybrid]\nswept = true\ntravel = 5\n").find("travel"), std::string::npos);
  EXPECT_EQ(parse_hybrid_config(good + "swept = true\ntravel = 1.5\n", "h.toml").options.travel, 1.5);
  EXPECT_NE(error_of("[hybrid]\nduration = 10\nframe_every = 20\n").find("frame_every"), std::string::npos);
  EXPECT_NE(error_of("[bins]\nbins = 20\n").find("[hybrid]"), std::string::npos);
  // Beds of several sizes: one fraction per size, summing to 1; a cell wide enough for the largest grain.
  const HybridConfig two = parse_hybrid_config(good + "sizes = [1.5, 0.5]\n", "h.toml");
  EXPECT_EQ(two.options.fractions, (std::vector<double>{0.5, 0.5}));
  EXPECT_NE(error_of(good + "sizes = [1.5, 0.5]\nfractions = [0.5, 0.6]\n").find("sum to 1"),
            std::string::npos);
  EXPECT_NE(error_of(good + "sizes = [1.5, 0.5]\nfractions = [1.0]\n").find("h.toml:8"), std::string::npos);
  EXPECT_NE(error_of(good + "sizes = [1.5]\n").find("sizes"), std::string::npos);
  EXPECT_NE(error_of(good + "sizes = [1.0, 2.5]\n").find("cell"), std::string::npos);
  // One size too: a grain raising its 1 d key point 0.87 d would always roll on (cell >= 1.16 d).
  EXPECT_NE(error_of("[hybrid]\nlength = 300\nwidth = 12\ncell = 1\n").find("cell >= 1.16"),
            std::string::npos);
  EXPECT_EQ(parse_hybrid_config("[hybrid]\nlength = 300\nwidth = 12\ncell = 1.25\n", "h.toml").options.cell,
            1.25);
  EXPECT_NE(error_of(good + "fractions = [0.5, 0.5]\n").find("needs sizes"), std::string::npos);
  EXPECT_NE(error_of(good + "sizes = [1.5, -0.5]\n").find("between"), std::string::npos);
  EXPECT_NE(error_of(good + "ejecta_size = \"big\"\n").find("ejecta_size"), std::string::npos);
  EXPECT_EQ(parse_hybrid_config(good + "ejecta_size = \"local\"\n", "h.toml").options.ejecta_size, "local");
}

TEST(HybridConfig, CommandLineOverridesReplaceOrAddKeysAndAreNamedWhenWrong) {
  const std::string good = "[hybrid]\nu_star = 35\nlength = 300\nwidth = 12\ncell = 2\nduration = 500\n";
  const HybridConfig c = parse_hybrid_config(
      good, "h.toml", {"u_star=36", "splash=lammel2017", "sizes=[1.5, 0.5]", "swept=true"});
  EXPECT_EQ(c.options.u_star, 36);            // replaced
  EXPECT_EQ(c.options.splash, "lammel2017");  // added, a bare word taken as a string
  EXPECT_EQ(c.options.sizes, (std::vector<double>{1.5, 0.5}));
  EXPECT_TRUE(c.options.swept);
  EXPECT_EQ(c.options.length, 300);  // the rest is the file's
  // The recorded text is the file's plus the overrides, so a checkpoint continues only under the same ones.
  EXPECT_EQ(c.text.substr(0, good.size()), good);
  EXPECT_NE(c.text.find("# --set u_star=36\n"), std::string::npos);
  EXPECT_EQ(parse_hybrid_config(good, "h.toml", {}).text, good);
  auto error_of = [&](const std::string& o) {
    try {
      parse_hybrid_config(good, "h.toml", {o});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Each mistake names the option as given, with no line number, and what is wrong.
  EXPECT_EQ(error_of("u_star=-3").rfind("--set u_star=-3: hybrid.u_star:", 0), 0u) << error_of("u_star=-3");
  EXPECT_NE(error_of("ustar=3").find("unknown key"), std::string::npos);
  EXPECT_EQ(error_of("ustar=3").rfind("--set ustar=3: ", 0), 0u);
  EXPECT_NE(error_of("u_star=abc").find("expected a number"), std::string::npos);
  EXPECT_NE(error_of("u_star").find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of("=3").find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of("a.b=3").find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of("u_star=3\nx = 4").find("one value"), std::string::npos);
  EXPECT_NE(error_of("u_star=[1,").find("not one TOML value"), std::string::npos);
  EXPECT_NE(error_of("frame_every=1000").find("frame_every"), std::string::npos);  // checks across keys hold
  // Random overrides are read or refused by name, never anything else.
  std::mt19937 rng(2031);
  auto uniform = [&] { return std::uniform_real_distribution<double>(0, 1)(rng); };
  const std::string alphabet = "u_star=swept[]\"'.,-+e0123456789 \n#truefalse";
  for (int k = 0; k < 3000; ++k) {
    std::string o;
    const int n = 1 + static_cast<int>(uniform() * 16);
    for (int i = 0; i < n; ++i) o += alphabet[static_cast<std::size_t>(uniform() * alphabet.size())];
    try {
      parse_hybrid_config(good, "h.toml", {o});
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--set ", 0), 0u) << e.what();
    }
  }
}

// The working directory for a scope: a config's splash file is read from it, as the command reads it.
struct InDirectory {
  std::filesystem::path before = std::filesystem::current_path();
  explicit InDirectory(const std::filesystem::path& p) { std::filesystem::current_path(p); }
  ~InDirectory() { std::filesystem::current_path(before); }
};

TEST(HybridConfig, ShippedConfigMutationsAreReadOrRefusedNeverCrash) {
  // hybrid_measured_splash.toml names data/splash/..., a path from the repository's top.
  const InDirectory top(GRAINLAB_SOURCE_DIR);
  for (const char* name : {"huo2021_ripples.toml", "hybrid_quick.toml", "hybrid_seeded.toml",
                           "hybrid_bidisperse.toml", "hybrid_measured_splash.toml"})
    fuzz_shipped_config(
        name,
        [](const std::string& text, const std::string& path) { return parse_hybrid_config(text, path); },
        [](const HybridConfig& c) {
          EXPECT_GT(c.options.u_star, 0);
          EXPECT_LE(3 * c.options.cell, c.options.width);
          EXPECT_LE(c.options.frame_every, c.options.duration);
          // A splash file is read as the command reads it, and then checked with the options.
          RippleOptions o = c.options;
          EXPECT_NO_THROW(validation::attach_recorded_splash(o));
          EXPECT_NO_THROW(check_ripple_options(o));
        },
        2030);
}

}  // namespace grainlab::ripples::hybrid
