// Hostile input: malformed scene files must end with exit status 2, a message naming the problem, no
// crash and no output file; a truncated run file must be refused on reading.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "cli_helpers.hpp"

namespace {

using namespace cli_test;

const std::string kBase = R"toml([scene]
duration = 0.002
effects = ["gravity", "normal_contact", "friction", "rotation"]
[accuracy]
integrator = "verlet"
dt = 1e-5
[materials.m]
k_n = 1e7
restitution = 0.5
k_s = 1e7
mu = 0.5
[[walls]]
type = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
[[bodies]]
radius = 1.0
density = 2.0
position = [0.0, 1.5]
[[bodies]]
shape = "polygon"
vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
density = 2.0
position = [5.0, 3.0]
)toml";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  if (at == std::string::npos) throw std::logic_error("fuzz: no '" + from + "' in the base scene");
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(Fuzz, HostileScenesAreRefusedByName) {
  Dir d;
  struct Bad {
    std::string scene, names;  // the message must contain `names`
  };
  std::string huge_lattice = kBase + R"toml(
[[assemblies]]
type = "lattice"
nx = 10000000
ny = 10000000
spacing = 2.0
origin = [20.0, 1.0]
radius = 1.0
density = 2.0
)toml";
  const std::vector<Bad> bad = {
      {replaced(kBase, "radius = 1.0", "radius = \"one\""), "bodies[0].radius"},
      {replaced(kBase, "radius = 1.0", "radius = nan"), "bodies[0].radius"},
      {replaced(kBase, "density = 2.0", "density = inf"), "bodies[0].density"},
      {replaced(kBase, "radius = 1.0", "radius = -1.0"), "bodies[0].radius"},
      {replaced(kBase, "position = [0.0, 1.5]", "position = [-inf, 1.5]"), "bodies[0].position"},
      {replaced(kBase, "position = [5.0, 3.0]", "position = [0.5, 1.5]"), "overlaps"},
      {replaced(kBase, "[scene]", "[scenery]"), "scene"},
      {replaced(kBase, "k_n = 1e7", ""), "k_n"},
      {replaced(kBase, "duration = 0.002", "duration = 1e300"), "accuracy.dt"},
      {replaced(kBase, "dt = 1e-5", "dt = 0.0"), "accuracy.dt"},
      {replaced(kBase, "restitution = 0.5", "restitution = 1.5"), "restitution"},
      {replaced(kBase, "vertices = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]",
                "vertices = [[-1.0, -1.0], [1.0, 1.0], [1.0, -1.0], [-1.0, 1.0]]"),
       "vertices"},
      {huge_lattice, "assemblies[0]"},
      {"", "scene"},
      {std::string("[scene]\nduration = \x01\xff\xfe\n"), "s.toml"},
      {std::string(4096, '['), "s.toml"},
      {"[scene]\nduration = 1.0\nduration = 2.0\n", "s.toml"},
  };
  for (std::size_t k = 0; k < bad.size(); ++k) {
    { std::ofstream(d.path / "s.toml", std::ios::binary) << bad[k].scene; }
    const fs::path out = d.path / "out.h5";
    const Outcome o =
        grainlab("run " + (d.path / "s.toml").string() + " --quiet --out " + out.string(), d.path);
    EXPECT_EQ(o.status, 2) << "case " << k << ": " << o.err;
    EXPECT_NE(o.err.find("grainlab: error:"), std::string::npos) << "case " << k << ": " << o.err;
    EXPECT_NE(o.err.find(bad[k].names), std::string::npos)
        << "case " << k << " should name " << bad[k].names << ": " << o.err;
    EXPECT_FALSE(fs::exists(out)) << "case " << k;
  }
}

TEST(Fuzz, RandomMutationsNeverCrashOrHalfWrite) {
  // Seeded byte-level mutations of a valid scene: each run either succeeds with a readable file or is
  // refused (status 2) with a message and no file. Anything else (a signal, status 1, a hang) fails.
  Dir d;
  std::mt19937_64 rng(2026);
  const std::string alphabet = "0123456789.-+e[]{}=\",\n #abcnaif";
  int accepted = 0, refused = 0;
  for (int k = 0; k < 120; ++k) {
    std::string s = kBase;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0:
          s[at] = alphabet[rng() % alphabet.size()];
          break;  // replace a byte
        case 1:
          s.erase(at, 1 + rng() % 8);
          break;  // delete a few
        default:
          s.insert(at, 1, alphabet[rng() % alphabet.size()]);  // insert one
      }
    }
    { std::ofstream(d.path / "s.toml", std::ios::binary) << s; }
    const fs::path out = d.path / "out.h5";
    fs::remove(out);
    const Outcome o =
        grainlab("run " + (d.path / "s.toml").string() + " --quiet --out " + out.string(), d.path);
    ASSERT_TRUE(o.status == 0 || o.status == 2) << "mutant " << k << " ended with " << o.status << ":\n"
                                                << s << "\n"
                                                << o.err;
    if (o.status == 0) {
      ++accepted;
      EXPECT_EQ(grainlab("inspect " + out.string(), d.path).status, 0) << "mutant " << k;
    } else {
      ++refused;
      EXPECT_NE(o.err.find("grainlab: error:"), std::string::npos) << "mutant " << k << ": " << o.err;
      EXPECT_FALSE(fs::exists(out)) << "mutant " << k;
    }
  }
  EXPECT_GT(refused, 0);
  RecordProperty("accepted", accepted);
  RecordProperty("refused", refused);
}

TEST(Fuzz, TruncatedRunFileIsRefusedOnReading) {
  Dir d;
  const fs::path good = d.path / "good.h5", cut = d.path / "cut.h5";
  { std::ofstream(d.path / "s.toml") << kBase; }
  ASSERT_EQ(
      grainlab("run " + (d.path / "s.toml").string() + " --quiet --out " + good.string(), d.path).status, 0);
  EXPECT_EQ(grainlab("inspect " + good.string(), d.path).status, 0);
  for (double fraction : {0.9, 0.5, 0.1}) {
    {
      std::ifstream in(good, std::ios::binary);
      std::string bytes((std::istreambuf_iterator<char>(in)), {});
      bytes.resize(static_cast<std::size_t>(bytes.size() * fraction));
      std::ofstream(cut, std::ios::binary) << bytes;
    }
    const Outcome o = grainlab("inspect " + cut.string(), d.path);
    EXPECT_EQ(o.status, 2) << "cut to " << fraction << ": " << o.err;
    EXPECT_NE(o.err.find("cut.h5"), std::string::npos) << o.err;
  }
  { std::ofstream(cut) << "not hdf5"; }
  EXPECT_EQ(grainlab("inspect " + cut.string(), d.path).status, 2);
}

TEST(Fuzz, DamagedRunFileDataIsRefusedOnReading) {
  // Every dataset carries a Fletcher-32 checksum: one flipped byte in frame 0's positions is caught.
  Dir d;
  const fs::path good = d.path / "good.h5", bad = d.path / "bad.h5";
  { std::ofstream(d.path / "s.toml") << kBase; }
  ASSERT_EQ(
      grainlab("run " + (d.path / "s.toml").string() + " --quiet --out " + good.string(), d.path).status, 0);
  ASSERT_TRUE(copy_with_damaged_data(good, bad, "/frames/000000/position"));
  const Outcome o = grainlab("inspect " + bad.string(), d.path);
  EXPECT_EQ(o.status, 2) << o.err;
  EXPECT_NE(o.err.find("position"), std::string::npos) << o.err;
  EXPECT_EQ(grainlab("inspect " + good.string(), d.path).status, 0);
}
