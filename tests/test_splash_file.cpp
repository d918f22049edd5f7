// The grainlab-splash/1 file: round trip, the sand-gun tables, and the fuzz tests every reader gets
// (truncated, damaged, foreign and malformed files are refused with a message naming the file).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <fstream>
#include <random>
#include <regex>

#include "cli_helpers.hpp"
#include "input_error.hpp"
#include "splash_file.hpp"

using grainlab::InputError;
using namespace grainlab::saltation;
using namespace cli_test;

namespace {

SplashFile tiny() {
  SplashFile f;
  f.text = {{"kind", "simulated"}, {"title", "test"}, {"engine", "native"}};
  f.grain_diameter_cm = 2, f.grain_density = 2;
  f.speeds = {10, 20};
  f.angles_deg = {15, 45};
  for (double v : f.speeds)
    for (double a : f.angles_deg) {
      SplashCell c;
      c.speed = v, c.angle_deg = a, c.impacts = 2;
      c.rebound = {{0, 1, 0.5 * v, 0.2 * v, -1}, {1, 0, 0, 0, 0}};
      c.ejecta = {{0, 0.1, 3, 0.1, 3.2, 0.5, -0.4, 1}};
      c.moments["rebound_probability"] = {0.5, 0.5, 0.1, 0.9};
      c.moments["ejecta_per_impact"] = {0.5, 0.7, 0, 1.5};
      f.cells.push_back(c);
    }
  return f;
}

// The same grid measured on spheres: every rebound and ejectum row has its lateral numbers.
SplashFile tiny3d() {
  SplashFile f = tiny();
  f.dimension = 3;
  for (SplashCell& c : f.cells) {
    c.rebound_lateral = {0.3, 0};
    c.ejecta_lateral = {{-0.7, 1.5}};
  }
  return f;
}

}  // namespace

TEST(SplashFile, LateralColumnsOfA3dFileSurviveTheRoundTrip) {
  Dir d;
  const std::string path = (d.path / "s3.h5").string();
  write_splash_file(path, tiny3d(), false);
  const SplashFile g = read_splash_file(path);
  EXPECT_EQ(g.dimension, 3);
  ASSERT_EQ(g.cells.size(), 4u);
  EXPECT_EQ(g.cell(1, 0).rebound_lateral, (std::vector<double>{0.3, 0}));
  ASSERT_EQ(g.cell(1, 1).ejecta_lateral.size(), 1u);
  EXPECT_EQ(g.cell(1, 1).ejecta_lateral[0][0], -0.7);
  EXPECT_EQ(g.cell(1, 1).ejecta_lateral[0][1], 1.5);
  EXPECT_EQ(g.cell(1, 1).ejecta, tiny().cells[3].ejecta);  // the 2-D columns as they were
  // A 2-D file says so, and carries no lateral rows.
  const std::string flat = (d.path / "s2.h5").string();
  write_splash_file(flat, tiny(), false);
  const SplashFile h = read_splash_file(flat);
  EXPECT_EQ(h.dimension, 2);
  EXPECT_TRUE(h.cell(0, 0).rebound_lateral.empty());
}

TEST(SplashFile, RoundTripKeepsEverything) {
  Dir d;
  const std::string path = (d.path / "s.h5").string();
  const SplashFile f = tiny();
  write_splash_file(path, f, false);
  const SplashFile g = read_splash_file(path);
  EXPECT_EQ(g.text.at("schema"), "grainlab-splash/1");
  EXPECT_EQ(g.text.at("kind"), "simulated");
  EXPECT_EQ(g.text.at("layout"), "grid");
  ASSERT_EQ(g.cells.size(), 4u);
  EXPECT_EQ(g.speeds, f.speeds);
  EXPECT_EQ(g.angles_deg, f.angles_deg);
  EXPECT_EQ(g.cell(1, 0).rebound, f.cells[2].rebound);
  EXPECT_EQ(g.cell(1, 1).ejecta, f.cells[3].ejecta);
  EXPECT_EQ(g.cell(0, 1).moments.at("ejecta_per_impact").hi, 1.5);
  EXPECT_DOUBLE_EQ(g.velocity_scale(), std::sqrt(981.0 * 2));
  EXPECT_EQ(&g.nearest(19, 40), &g.cell(1, 1));
  EXPECT_EQ(&g.nearest(9, 10), &g.cell(0, 0));
  EXPECT_THROW(write_splash_file(path, f, false), std::runtime_error);  // exists
}

TEST(SplashFile, SandGunTablesAsAMeasuredFile) {
  Dir d;
  const std::string path = (d.path / "sg.h5").string();
  write_splash_file(path, sand_gun_splash(), false);
  const SplashFile g = read_splash_file(path);
  EXPECT_EQ(g.text.at("kind"), "measured");
  EXPECT_EQ(g.text.at("layout"), "scattered");
  ASSERT_EQ(g.cells.size(), 9u);
  // Table 3.11 row 1: 650 cm/s at 15 deg, eps_iy 0.80 (0.43) over 12 events; Table 3.12: 2.8 ejecta.
  const SplashCell& c = g.nearest(650 / g.velocity_scale(), 15);
  EXPECT_NEAR(c.speed * g.velocity_scale(), 650, 1e-9);
  EXPECT_EQ(c.moments.at("eps_iy").mean, 0.80);
  EXPECT_NEAR(c.moments.at("eps_iy").hi - 0.80, 1.959963984540054 * 0.43 / std::sqrt(12.0), 1e-12);
  EXPECT_EQ(c.moments.at("ejecta_per_impact").mean, 2.8);
  EXPECT_TRUE(c.rebound.empty());
}

namespace {

// Rewrites one attribute (string) of a copy of the file.
void set_string_attribute(const fs::path& file, const char* name, const std::string& value) {
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Adelete(f, name);
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size());
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(f, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, type, value.c_str());
  H5Aclose(a), H5Sclose(space), H5Tclose(type), H5Fclose(f);
}

void expect_refused(const fs::path& p, const std::string& says) {
  try {
    read_splash_file(p.string());
    ADD_FAILURE() << p << " was accepted";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find(p.filename().string()), std::string::npos) << w;
    EXPECT_NE(w.find(says), std::string::npos) << "expected \"" << says << "\" in: " << w;
  }
}

}  // namespace

TEST(SplashFileFuzz, ForeignTruncatedAndDamagedFilesAreRefusedByName) {
  Dir d;
  const fs::path good = d.path / "good.h5";
  write_splash_file(good.string(), tiny(), false);
  const fs::path junk = d.path / "junk.h5";
  { std::ofstream(junk) << "not hdf5"; }
  expect_refused(junk, "not an HDF5 file");
  expect_refused(d.path / "missing.h5", "does not exist");
  expect_refused(d.path, "is a folder, not a file");
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (double f : {0.95, 0.7, 0.4, 0.1}) {
    const fs::path cut = d.path / "cut.h5";
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, static_cast<std::size_t>(bytes.size() * f));
    EXPECT_THROW(read_splash_file(cut.string()), InputError) << "cut to " << f;
  }
  const fs::path bad = d.path / "bad.h5";
  ASSERT_TRUE(copy_with_damaged_data(good, bad, "/cells/0001/rebound"));
  expect_refused(bad, "rebound");
  const fs::path schema = d.path / "schema.h5";
  fs::copy_file(good, schema);
  set_string_attribute(schema, "schema", "grainlab-splash/2");
  expect_refused(schema, "grainlab-splash/2");
  const fs::path kind = d.path / "kind.h5";
  fs::copy_file(good, kind);
  set_string_attribute(kind, "kind", "guessed");
  expect_refused(kind, "kind");
  // A run file is HDF5 but not a splash file.
  const Outcome o =
      cli_test::grainlab("run " + std::string(GRAINLAB_SOURCE_DIR) +
                             "/scenes/two_disc_collision.toml --quiet --out " + (d.path / "run.h5").string(),
                         d.path);
  ASSERT_EQ(o.status, 0) << o.err;
  expect_refused(d.path / "run.h5", "schema");
}

TEST(SplashFileFuzz, Damaged3dFilesAreRefusedByName) {
  Dir d;
  const fs::path good = d.path / "good3.h5";
  write_splash_file(good.string(), tiny3d(), false);
  const fs::path bad = d.path / "bad3.h5";
  ASSERT_TRUE(copy_with_damaged_data(good, bad, "/cells/0002/ejecta_lateral"));
  expect_refused(bad, "ejecta_lateral");
  // A lateral dataset taken away, or one of the wrong length.
  const fs::path gone = d.path / "gone3.h5";
  fs::copy_file(good, gone);
  {
    hid_t f = H5Fopen(gone.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Ldelete(f, "/cells/0001/rebound_lateral", H5P_DEFAULT);
    H5Fclose(f);
  }
  expect_refused(gone, "rebound_lateral is missing");
  SplashFile shorter = tiny3d();
  shorter.cells[3].rebound_lateral = {0.1};
  const fs::path rows = d.path / "rows3.h5";
  write_splash_file(rows.string(), shorter, false);
  expect_refused(rows, "rebound_lateral has 1 rows but rebound has 2");
  // A dimension other than 2 or 3.
  SplashFile four = tiny3d();
  four.dimension = 4;
  const fs::path dim = d.path / "dim4.h5";
  write_splash_file(dim.string(), four, false);
  expect_refused(dim, "dimension 4");
}

TEST(SplashFileFuzz, RandomByteFlipsNeverCrash) {
  // Seeded corruption anywhere in the file: each mutant is read cleanly or refused with InputError.
  Dir d;
  std::mt19937_64 rng(2026);
  for (const SplashFile& file : {tiny(), tiny3d()}) {
    const fs::path good = d.path / "good.h5";
    write_splash_file(good.string(), file, true);
    std::ifstream in(good, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    int refused = 0;
    for (int k = 0; k < 200; ++k) {
      std::string s = bytes;
      for (int e = 0; e < 1 + static_cast<int>(rng() % 3); ++e)
        s[rng() % s.size()] ^= static_cast<char>(1 + rng() % 255);
      const fs::path m = d.path / "m.h5";
      std::ofstream(m, std::ios::binary) << s;
      try {
        const SplashFile f = read_splash_file(m.string());
        EXPECT_FALSE(f.cells.empty());
      } catch (const InputError&) {
        ++refused;
      }
    }
    EXPECT_GT(refused, 0);
  }
}

TEST(SplashFile, CommandWritesAReadableFileAndTheSandGun) {
  Dir d;
  const fs::path s = d.path / "sg.h5";
  Outcome o = cli_test::grainlab("splash --sand-gun --out " + s.string(), d.path);
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(read_splash_file(s.string()).text.at("kind"), "measured");
  o = cli_test::grainlab("splash --sand-gun --out " + s.string(), d.path);
  EXPECT_EQ(o.status, 2);  // exists
  o = cli_test::grainlab("splash --out x.h5 --angles 95", d.path);
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.err.find("--angles"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(d.path / "x.h5"));
}

TEST(Layering, SaltationNeverIncludesTheEngine) {
  // design.md: the DEM's impacts reach saltation/ only through the splash file.
  for (const auto& entry : fs::directory_iterator(fs::path(GRAINLAB_SOURCE_DIR) / "saltation")) {
    std::ifstream in(entry.path());
    std::string line;
    const std::regex include(R"(#include\s+"([^"]+)\")");
    while (std::getline(in, line)) {
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      for (const char* forbidden : {"world", "engine", "native", "backend", "domain", "particles", "impact"})
        EXPECT_EQ(m[1].str().find(forbidden), std::string::npos) << entry.path() << ": " << line;
    }
  }
}
