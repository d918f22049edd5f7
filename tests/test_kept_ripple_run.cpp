// The hybrid suite's kept ripple run (validation/kept_ripple_run.hpp): a run stopped after a frame and
// continued from its file ends with the frames and bed of one never stopped, bit for bit; another run's
// file and damaged files are refused by name, never taken.
#include <gtest/gtest.h>

#include <cstring>

#include "cli_helpers.hpp"
#include "frame_tables.hpp"
#include "input_error.hpp"
#include "kept_ripple_run.hpp"

namespace {

using namespace cli_test;
using grainlab::InputError;
using grainlab::ripples::hybrid::BedFrame;
using grainlab::ripples::hybrid::frame_history_row;
using grainlab::ripples::hybrid::RippleOptions;
using grainlab::ripples::hybrid::RippleRun;
using grainlab::validation::kept_ripple_frames;
using grainlab::validation::run_frames;
using grainlab::validation::SuiteOptions;

struct Stop {};  // thrown by the progress callback: the suite stopped after a frame

// A small bed of two sizes (so the surface sizes are kept too), five frames.
RippleOptions small_run() {
  RippleOptions o;
  o.u_star = 40, o.length = 120, o.width = 8, o.triggers = 10, o.duration = 400, o.frame_every = 100;
  o.sizes = {1.5, 0.5}, o.fractions = {0.5, 0.5};
  return o;
}

SuiteOptions kept_in(const Dir& d) {
  SuiteOptions so;
  so.ensembles_dir = d.path.string();
  return so;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

void expect_same_frames(const std::vector<BedFrame>& a, const std::vector<BedFrame>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(same_bits(frame_history_row(a[k]), frame_history_row(b[k]))) << "frame " << k;
    EXPECT_TRUE(same_bits(a[k].profile, b[k].profile)) << "frame " << k;
    EXPECT_TRUE(same_bits(a[k].size_profile, b[k].size_profile)) << "frame " << k;
    EXPECT_EQ(a[k].dx, b[k].dx);
  }
}

// Runs the kept run until `frames` frames are kept, then stops it as a signal would between frames.
void run_and_stop(const RippleOptions& o, const SuiteOptions& so, std::size_t frames) {
  SuiteOptions stopping = so;
  stopping.progress = [frames](std::size_t done, std::size_t) {
    if (done >= frames) throw Stop{};
  };
  RippleRun run(o);
  EXPECT_THROW(kept_ripple_frames(run, o, stopping, "ripple-run"), Stop);
}

TEST(HybridSuiteRippleRun, AStoppedRunContinuesToTheFramesOfOneNeverStopped) {
  const RippleOptions o = small_run();
  RippleRun straight(o);
  const std::vector<BedFrame> expected = run_frames(straight, o);
  ASSERT_EQ(expected.size(), 5u);
  Dir d;
  SuiteOptions so = kept_in(d);
  run_and_stop(o, so, 3);
  std::vector<std::size_t> told;
  std::vector<std::string> said;
  so.progress = [&](std::size_t done, std::size_t total) {
    told.push_back(done);
    EXPECT_EQ(total, 5u);
  };
  so.log = [&](const std::string& line) { said.push_back(line); };
  RippleRun continued(o);
  const std::vector<BedFrame> frames = kept_ripple_frames(continued, o, so, "ripple-run");
  EXPECT_EQ(told, (std::vector<std::size_t>{3, 4, 5}));
  ASSERT_EQ(said.size(), 1u);
  EXPECT_NE(said[0].find("from t* = 200"), std::string::npos) << said[0];
  expect_same_frames(frames, expected);
  EXPECT_EQ(continued.bed().heights(), straight.bed().heights());
  EXPECT_EQ(continued.bed().layer()->amounts(), straight.bed().layer()->amounts());
  EXPECT_EQ(continued.transport().airborne(), straight.transport().airborne());
  // Finished: taken whole from the file, nothing run.
  RippleRun again(o);
  expect_same_frames(kept_ripple_frames(again, o, so, "ripple-run"), expected);
  EXPECT_EQ(again.bed().heights(), straight.bed().heights());
}

TEST(HybridSuiteRippleRun, AnotherRunsFileIsRefusedByName) {
  const RippleOptions o = small_run();
  Dir d;
  const SuiteOptions so = kept_in(d);
  run_and_stop(o, so, 2);
  RippleOptions other = o;
  other.u_star = 45;
  RippleRun run(other);
  try {
    kept_ripple_frames(run, other, so, "ripple-run");
    FAIL() << "another run's file was taken";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ripple-run.ck.h5"), std::string::npos) << m;
    EXPECT_NE(m.find("another run"), std::string::npos) << m;
  }
}

// A bit flipped in each of the kept tables: refused with the file's name, or (a flip that leaves the
// numbers readable) continued; never a crash.
TEST(HybridSuiteRippleRun, DamagedFilesAreRefusedOrReadNeverCrash) {
  RippleOptions o = small_run();
  o.duration = 200;
  Dir d;
  const SuiteOptions so = kept_in(d);
  run_and_stop(o, so, 2);
  const fs::path kept = d.path / "ripple-run.ck.h5", good = d.path / "good.h5";
  fs::copy_file(kept, good);
  int refused = 0, read = 0;
  for (const std::string dataset :
       {"frames/history", "frames/profiles", "frames/size_profiles", "run/bed", "run/clock", "run/layer",
        "run/last_frame", "run/series", "run/transport/grains"}) {
    ASSERT_TRUE(copy_with_damaged_data(good, kept, dataset)) << dataset;
    RippleRun run(o);
    try {
      kept_ripple_frames(run, o, so, "ripple-run");
      ++read;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("ripple-run.ck.h5"), std::string::npos) << e.what();
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);  // (the checksums catch most flips)
}

}  // namespace
