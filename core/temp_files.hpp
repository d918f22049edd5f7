#pragma once
// Temporary files that a run stopped by a signal removes. Output is written under a temporary name and
// renamed into place when whole; a run that fails removes its temporary as the writer is destroyed, but
// one stopped by Ctrl-C (SIGINT), SIGTERM (mpirun, batch systems) or SIGHUP never reaches a destructor and
// would leave a file as large as the output beside it. While a file is held here, such a signal removes
// it before the process ends as the signal says. (SIGKILL cannot be caught: nothing can clean up after it.)
#include <string>

namespace grainlab {

// Holds `path` (made absolute) for removal by SIGINT, SIGTERM or SIGHUP until destroyed or released. The
// handler is installed at the first hold, for each of those signals whose disposition is still the default
// (one ignored on purpose, as nohup ignores SIGHUP, stays ignored). At most kMaxHeld paths at once; beyond
// that, or for a path longer than the slot, the file is simply not held (what happened without this).
class TempFileHold {
 public:
  static constexpr int kMaxHeld = 32;
  explicit TempFileHold(const std::string& path);
  ~TempFileHold() { release(); }
  TempFileHold(const TempFileHold&) = delete;
  TempFileHold& operator=(const TempFileHold&) = delete;
  // No longer removed by a signal (the file was renamed into place or removed).
  void release();

 private:
  int slot_ = -1;
};

}  // namespace grainlab
