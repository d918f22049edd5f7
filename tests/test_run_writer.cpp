// The run file's writer streams: each frame is on disk (in the temporary file) once added, the run file
// appears only on commit, and a writer dropped before committing leaves nothing behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_helpers.hpp"
#include "h5_input.hpp"
#include "h5_output.hpp"

namespace {

using namespace cli_test;

grainlab::Frame spheres(double t, int n) {
  grainlab::Frame f;
  f.time = t;
  for (int i = 0; i < n; ++i) {
    const double x[3] = {1.0 * i, 2.0, 3.0 + t}, v[3] = {0, 0, -9.81 * t}, q[4] = {1, 0, 0, 0},
                 w[3] = {0, 0.5, 0};
    f.add_body3d(i, x, v, q, w, 1.0, -1);
  }
  return f;
}

// The writer's temporary file (its name carries the process id).
fs::path temporary_of(const fs::path& out) {
  for (const auto& e : fs::directory_iterator(out.parent_path()))
    if (e.path().filename().string().rfind(out.filename().string() + ".tmp-", 0) == 0) return e.path();
  return {};
}

TEST(RunWriter, EachFrameIsOnDiskWhenAdded) {
  Dir d;
  const fs::path out = d.path / "run.h5";
  grainlab::RunWriter w(out.string(), false);
  for (int k = 0; k < 3; ++k) {
    w.add_frame(spheres(0.1 * k, 50));
    const fs::path tmp = temporary_of(out);
    ASSERT_FALSE(tmp.empty());
    // Read back from the file while the writer still holds it: every frame so far, intact.
    int seen = 0;
    grainlab::read_frames(tmp.string(), "/frames", static_cast<std::size_t>(k) + 1,
                          [&](const grainlab::Frame& f) {
                            EXPECT_EQ(f.id.size(), 50u);
                            EXPECT_DOUBLE_EQ(f.time, 0.1 * seen);
                            EXPECT_DOUBLE_EQ(f.position[3 * 7 + 2], 3.0 + 0.1 * seen);
                            EXPECT_TRUE(f.angle.empty()) << "3-D frames carry no 2-D angle";
                            ++seen;
                          });
    EXPECT_EQ(seen, k + 1);
  }
  EXPECT_FALSE(fs::exists(out)) << "the run file appears only on commit";
  w.set_metadata({{{"grainlab_version", GRAINLAB_VERSION}}, {}});
  w.set_energy_columns({"time", "total"});
  for (int k = 0; k < 3; ++k) w.add_energy_row({0.1 * k, 1.0});
  const std::string xmf = w.commit();
  EXPECT_TRUE(fs::exists(xmf));
  EXPECT_TRUE(temporary_of(out).empty());
  const grainlab::RunFileSummary s = grainlab::read_run_file(out.string());
  EXPECT_EQ(s.frames, 3u);
  EXPECT_EQ(s.bodies, 50u);
  EXPECT_DOUBLE_EQ(s.last_time, 0.2);
}

TEST(RunWriter, UncommittedLeavesNothing) {
  Dir d;
  const fs::path out = d.path / "run.h5";
  {
    grainlab::RunWriter w(out.string(), false);
    w.add_frame(spheres(0, 10));
    EXPECT_FALSE(temporary_of(out).empty());
  }
  EXPECT_TRUE(temporary_of(out).empty());
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
