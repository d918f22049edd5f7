#pragma once
// Running the grainlab binary from a test: exit status and stderr, in a scratch folder of its own.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace cli_test {

struct Outcome {
  int status = -1;  // exit status; -1 if killed by a signal
  std::string err, out;
};

inline std::string file_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs grainlab with `args` (at most 20 s), stderr and stdout captured.
inline Outcome grainlab(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt", out = dir / "stdout.txt";
  const std::string cmd = "timeout 20 " + std::string(GRAINLAB_BINARY) + " " + args + " > " + out.string() +
                          " 2> " + err.string();
  const int raw = std::system(cmd.c_str());
  Outcome o;
  o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  o.err = file_text(err), o.out = file_text(out);
  return o;
}

struct Dir {
  fs::path path;
  Dir() {
    path = fs::temp_directory_path() / ("grainlab-test-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~Dir() { fs::remove_all(path); }
};

// Flips one bit in the stored data of `dataset` (its first chunk) in a copy of `from` written to `to`;
// returns false if the dataset or its chunk cannot be found.
inline bool copy_with_damaged_data(const fs::path& from, const fs::path& to, const std::string& dataset) {
  haddr_t where = 0;
  hsize_t size = 0;
  {
    hid_t f = H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) return false;
    hid_t ds = H5Dopen2(f, dataset.c_str(), H5P_DEFAULT);
    hsize_t offset[2];
    unsigned mask = 0;
    hid_t space = H5Dget_space(ds);
    const herr_t found = ds < 0 ? -1 : H5Dget_chunk_info(ds, space, 0, offset, &mask, &where, &size);
    H5Sclose(space), H5Dclose(ds), H5Fclose(f);
    if (found < 0 || size <= 8) return false;
  }
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  std::fstream io(to, std::ios::in | std::ios::out | std::ios::binary);
  io.seekg(static_cast<std::streamoff>(where + 3));
  char c = 0;
  io.get(c);
  io.seekp(static_cast<std::streamoff>(where + 3));
  io.put(static_cast<char>(c ^ 0x40));
  return static_cast<bool>(io);
}

}  // namespace cli_test
