// The reader of height-field files (`ripples hybrid --out`: /frames/NNNNNN, ny x nx): damaged, cut or
// non-finite frames are refused with InputError naming the frame, never half-read or crashed on.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "cli_helpers.hpp"
#include "h5_input.hpp"
#include "h5_output.hpp"
#include "input_error.hpp"

using cli_test::copy_with_damaged_data;
using cli_test::Dir;
namespace {

// A height field of three 4 x 6 frames, as `ripples hybrid --out` writes its bed.
fs::path write_grid_file(const fs::path& dir, double poison = 0) {
  const fs::path path = dir / "grid.h5";
  grainlab::GridSeriesWriter w(path.string(), true, 6, 4, 2.0, "height");
  for (int k = 0; k < 3; ++k) {
    std::vector<double> h(24);
    for (std::size_t i = 0; i < h.size(); ++i) h[i] = 0.1 * k + 0.01 * static_cast<double>(i);
    if (k == 2 && poison != 0) h[5] = poison;
    w.add_frame(100.0 * k, h);
  }
  w.commit({}, {{"grainlab_version", "test"}, {"dx", "2"}});
  return path;
}

void expect_refused(const fs::path& path, std::size_t frame, const std::string& says) {
  try {
    grainlab::read_grid_frame(path.string(), frame);
    ADD_FAILURE() << path << " frame " << frame << " was read";
  } catch (const grainlab::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(GridFrameFuzz, DamagedCutOrNotFiniteFramesAreRefusedByName) {
  Dir d;
  const fs::path good = write_grid_file(d.path);
  const grainlab::GridFrame f = grainlab::read_grid_frame(good.string(), 1);
  EXPECT_EQ(f.nx, 6u);
  EXPECT_EQ(f.ny, 4u);
  EXPECT_EQ(f.time, 100.0);
  EXPECT_DOUBLE_EQ(f.values[7], 0.1 + 0.07);  // row 1, x 1
  expect_refused(good, 3, "/frames/000003");
  // One flipped byte in a frame's data fails its checksum.
  const fs::path bad = d.path / "bad.h5";
  ASSERT_TRUE(copy_with_damaged_data(good, bad, "/frames/000001"));
  expect_refused(bad, 1, "/frames/000001");
  EXPECT_EQ(grainlab::read_grid_frame(bad.string(), 0).values,
            grainlab::read_grid_frame(good.string(), 0).values);
  // Cut files and random damage: every frame is read whole or refused with InputError, never a crash.
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  std::mt19937_64 rng(2026);
  int refused = 0;
  for (int k = 0; k < 150; ++k) {
    std::string s = bytes;
    if (k < 10)
      s.resize(s.size() * static_cast<std::size_t>(k + 1) / 11);
    else
      for (int e = 0; e < 1 + static_cast<int>(rng() % 3); ++e)
        s[rng() % s.size()] ^= static_cast<char>(1 + rng() % 255);
    const fs::path m = d.path / "m.h5";
    std::ofstream(m, std::ios::binary) << s;
    for (std::size_t frame = 0; frame < 3; ++frame) try {
        EXPECT_EQ(grainlab::read_grid_frame(m.string(), frame).values.size(), 24u);
      } catch (const grainlab::InputError&) {
        ++refused;
      }
  }
  EXPECT_GE(refused, 10);
  // A height that is not a number is named, not analysed.
  expect_refused(write_grid_file(d.path, std::nan("")), 2, "not a finite number");
}
