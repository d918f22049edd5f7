// The grainlab command end to end: HDF5 + XDMF output with metadata, exit status 2 on bad input with
// nothing written, no overwriting without --force.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "engine.hpp"
#include "scene.hpp"

namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("grainlab-test-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

int run_grainlab(const std::string& args) {
  const int status = std::system((std::string(GRAINLAB_BINARY) + " " + args + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read_string_attr(hid_t f, const char* name) {
  hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  hid_t t = H5Aget_type(a);
  std::string s(H5Tget_size(t), '\0');
  H5Aread(a, t, s.data());
  H5Tclose(t), H5Aclose(a);
  return s;
}

const std::string kScene = std::string(GRAINLAB_SOURCE_DIR) + "/scenes/two_disc_collision.toml";

}  // namespace

TEST(Command, RunWritesHdf5WithMetadataAndXdmf) {
  TempDir d;
  const fs::path out = d.path / "pair.h5";
  ASSERT_EQ(run_grainlab("run " + kScene + " --quiet --out " + out.string()), 0);
  ASSERT_TRUE(fs::exists(out));
  ASSERT_TRUE(fs::exists(d.path / "pair.xmf"));
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_EQ(read_string_attr(f, "active_effects"), "normal_contact");
  EXPECT_NE(read_string_attr(f, "scene_text").find("[scene]"), std::string::npos);
  EXPECT_EQ(read_string_attr(f, "engine"), "native");
  EXPECT_GT(H5Lexists(f, "/frames/000000/position", H5P_DEFAULT), 0);
  EXPECT_GT(H5Lexists(f, "/energy/total", H5P_DEFAULT), 0);
  EXPECT_GT(H5Aexists_by_name(f, "/diagnostics", "rejected_steps", H5P_DEFAULT), 0);
  H5Fclose(f);
  std::ifstream xmf(d.path / "pair.xmf");
  const std::string text((std::istreambuf_iterator<char>(xmf)), {});
  EXPECT_NE(text.find("pair.h5:/frames/000000/position"), std::string::npos);
  // No temporary files left behind.
  for (const auto& e : fs::directory_iterator(d.path))
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos);
}

TEST(Command, ExistingOutputIsNotOverwrittenWithoutForce) {
  TempDir d;
  const fs::path out = d.path / "pair.h5";
  { std::ofstream(out) << "keep me"; }
  EXPECT_EQ(run_grainlab("run " + kScene + " --quiet --out " + out.string()), 2);
  EXPECT_EQ(fs::file_size(out), 7u);
  EXPECT_EQ(run_grainlab("run " + kScene + " --quiet --force --out " + out.string()), 0);
  EXPECT_GT(fs::file_size(out), 7u);
}

TEST(Command, BadInputExitsTwoAndWritesNothing) {
  TempDir d;
  const fs::path out = d.path / "x.h5";
  const fs::path bad = d.path / "bad.toml";
  { std::ofstream(bad) << "[scene]\nduration = -1\neffects = []\n"; }
  EXPECT_EQ(run_grainlab("run " + bad.string() + " --quiet --out " + out.string()), 2);
  EXPECT_EQ(run_grainlab("run " + kScene + " --quiet --set scene.duration=abc --out " + out.string()), 2);
  EXPECT_EQ(run_grainlab("run " + kScene + " --quiet --set accuracy.dt=0 --out " + out.string()), 2);
  EXPECT_EQ(run_grainlab("run " + (d.path / "missing.toml").string() + " --quiet"), 2);
  EXPECT_EQ(run_grainlab("bench bed --nx 0"), 2);
  // Peers are checked as engines are (a misspelt one was reported as --engine), and native is not its own
  // peer.
  EXPECT_EQ(run_grainlab("bench impact --repeats 1 --peers foo"), 2);
  EXPECT_EQ(run_grainlab("bench impact --repeats 1 --peers native"), 2);
  EXPECT_EQ(run_grainlab("validate --suite no-such-suite --out " + (d.path / "r").string()), 2);
  EXPECT_TRUE(fs::is_empty(d.path / "bad.toml") == false);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(d.path / "r"));
}

namespace {
std::vector<double> read_doubles(hid_t f, const char* path) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  hid_t s = H5Dget_space(d);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(s)));
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(s), H5Dclose(d);
  return v;
}
}  // namespace

// [output] contacts = true: the Table 2.1 collision is one event whose impulse is each grain's momentum
// change m v (1 + eps) with the thesis's eps = 0.6706, beginning when the 0.2 cm gap has closed.
TEST(Command, ContactEventsAreWrittenWhenAsked) {
  TempDir d;
  const fs::path out = d.path / "pair.h5";
  ASSERT_EQ(run_grainlab("run " + kScene + " --quiet --set output.contacts=true --out " + out.string()), 0);
  hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  ASSERT_GT(H5Lexists(f, "/contact_events", H5P_DEFAULT), 0);
  const auto a = read_doubles(f, "/contact_events/body_a"), b = read_doubles(f, "/contact_events/body_b");
  const auto begin = read_doubles(f, "/contact_events/t_begin"),
             open = read_doubles(f, "/contact_events/open");
  const auto impulse = read_doubles(f, "/contact_events/normal_impulse");
  H5Fclose(f);
  ASSERT_EQ(impulse.size(), 1u);
  EXPECT_EQ(a[0], 1);
  EXPECT_EQ(b[0], 0);
  EXPECT_EQ(open[0], 0);
  const double m = 2.0 * M_PI;
  EXPECT_NEAR(impulse[0], m * 50.0 * (1 + 0.67064), 0.005 * m * 50.0 * 1.67064);
  // t_begin is the start of the step in which the gap closed (steps are at most dt_max = 1e-4 s).
  EXPECT_LE(begin[0], 0.2 / 100.0);
  EXPECT_GT(begin[0], 0.2 / 100.0 - 1e-4);

  // Not asked: no group.
  const fs::path plain = d.path / "plain.h5";
  ASSERT_EQ(run_grainlab("run " + kScene + " --quiet --out " + plain.string()), 0);
  f = H5Fopen(plain.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  EXPECT_EQ(H5Lexists(f, "/contact_events", H5P_DEFAULT), 0);
  H5Fclose(f);
}

// Every scene shipped in scenes/ runs on every engine whose capabilities cover it (shortened to 0.002 s
// of scene time: 40 steps of the 20,000-disc avalanche, which ODE takes 14 s over), and any other engine
// refuses it with exit status 2 and a message naming itself.
TEST(Command, EveryShippedSceneRunsWhereSupportedAndIsRefusedClearlyElsewhere) {
  TempDir d;
  int runs = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(GRAINLAB_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const grainlab::Scene scene = grainlab::load_scene(entry.path().string());
    for (const grainlab::Capabilities& c : grainlab::engine_catalog()) {
      bool supported = true;
      try {
        grainlab::check_engine_supports(c, scene);
      } catch (const std::exception&) {
        supported = false;
      }
      const std::string what = c.name + " on " + entry.path().filename().string();
      EXPECT_TRUE(supported || c.name != "native") << what;
      const fs::path out = d.path / (c.name + "-" + entry.path().stem().string() + ".h5");
      const fs::path err = d.path / "stderr.txt";
      const int status = std::system((std::string(GRAINLAB_BINARY) + " run " + entry.path().string() +
                                      " --engine " + c.name + " --quiet --set scene.duration=0.002 --out " +
                                      out.string() + " > /dev/null 2> " + err.string())
                                         .c_str());
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
      std::ifstream in(err);
      const std::string message((std::istreambuf_iterator<char>(in)), {});
      if (supported) {
        EXPECT_EQ(code, 0) << what << ": " << message;
        EXPECT_TRUE(fs::exists(out)) << what;
        ++runs;
      } else {
        EXPECT_EQ(code, 2) << what;
        EXPECT_NE(message.find(c.name), std::string::npos) << what << ": " << message;
        EXPECT_FALSE(fs::exists(out)) << what;
      }
    }
  }
  EXPECT_GE(runs, 10);  // the engines do run most of the shipped scenes
}
