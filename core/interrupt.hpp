#pragma once
// What a run stopped by a signal cleans up. Output is written under a temporary name and renamed into
// place when whole; a run that fails removes its temporary as the writer is destroyed, but one stopped by
// Ctrl-C (SIGINT), SIGTERM (mpirun, batch systems) or SIGHUP never reaches a destructor: it would leave a
// file as large as the output beside it, and child processes (`validate --jobs`) running on. While held
// here, such a signal removes the temporary files and passes itself on to the children before the process
// ends as the signal says. (SIGKILL cannot be caught: nothing can clean up after it.)
#include <sys/types.h>

#include <string>

namespace grainlab {

// The handler is installed at the first hold, for each of SIGINT, SIGTERM and SIGHUP whose disposition is
// still the default (one ignored on purpose, as nohup ignores SIGHUP, stays ignored). At most kMaxHeld
// files and kMaxHeld children at once; beyond that, or for a path longer than a slot, nothing is held
// (what happened without this).
constexpr int kMaxHeld = 32;

// Holds `path` (made absolute) for removal by the signal until destroyed or released.
class TempFileHold {
 public:
  explicit TempFileHold(const std::string& path);
  ~TempFileHold() { release(); }
  TempFileHold(const TempFileHold&) = delete;
  TempFileHold& operator=(const TempFileHold&) = delete;
  // No longer removed by a signal (the file was renamed into place or removed).
  void release();

 private:
  int slot_ = -1;
};

// Holds a child process to be sent the same signal until destroyed or released (when it has been waited
// for). The child should be in a process group of its own, so that a terminal's Ctrl-C reaches it once,
// through the parent, and the parent knows to wait for it.
class ChildHold {
 public:
  explicit ChildHold(pid_t child);
  ~ChildHold() { release(); }
  ChildHold(const ChildHold&) = delete;
  ChildHold& operator=(const ChildHold&) = delete;
  ChildHold(ChildHold&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  void release();

 private:
  int slot_ = -1;
};

}  // namespace grainlab
