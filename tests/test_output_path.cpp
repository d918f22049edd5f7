// Output paths are refused when the command line is read, before hours of work (cli/output_path.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../cli/output_path.hpp"

namespace grainlab::cli {
namespace {

namespace fs = std::filesystem;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / fmt::format("grainlab-output-path-{}", ::getpid());
  Scratch() {
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "a-file") << "x";
  }
  ~Scratch() { fs::remove_all(dir); }
  std::string at(const std::string& rest) const { return (dir / rest).string(); }
};

TEST(OutputPath, AFileNeedsAnExistingWritableFolder) {
  const Scratch s;
  EXPECT_EQ(output_path_problem("", false), "");  // no output asked for
  EXPECT_EQ(output_path_problem(s.at("run.h5"), false), "");
  EXPECT_EQ(output_path_problem(s.at("a-file"), false), "");  // overwriting is --force's business
  EXPECT_NE(output_path_problem(s.at("missing/run.h5"), false).find("does not exist"), std::string::npos);
  EXPECT_NE(output_path_problem(s.at("a-file/run.h5"), false).find("is not a folder"), std::string::npos);
  EXPECT_NE(output_path_problem(s.dir.string(), false).find("is a folder"), std::string::npos);
}

TEST(OutputPath, AFolderMayHaveMissingParentsButNoFileInTheWay) {
  const Scratch s;
  EXPECT_EQ(output_path_problem(s.at("report"), true), "");
  EXPECT_EQ(output_path_problem(s.at("new/deeper/report"), true), "");  // made with its parents
  EXPECT_EQ(output_path_problem(s.dir.string(), true), "");             // an existing folder
  EXPECT_NE(output_path_problem(s.at("a-file"), true).find("not a folder"), std::string::npos);
  EXPECT_NE(output_path_problem(s.at("a-file/report"), true).find("is not a folder"), std::string::npos);
}

TEST(OutputPath, TheCommandLineRefusesABadPathWithItsOptionName) {
  const Scratch s;
  CLI::App app;
  std::string out;
  app.add_option("--out", out)->check(output_file());
  EXPECT_NO_THROW(app.parse(std::vector<std::string>{s.at("fine.h5"), "--out"}));
  try {
    app.parse(std::vector<std::string>{s.at("missing/x.h5"), "--out"});  // CLI11 reads the vector backwards
    FAIL() << "a missing folder was accepted";
  } catch (const CLI::ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("--out"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grainlab::cli
