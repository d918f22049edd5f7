#include "interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <filesystem>

namespace grainlab {

namespace {

// Fixed slots, so the handler reads only memory that never moves and calls only unlink, kill, sigaction and
// raise (async-signal-safe). A slot's content is written before it is marked held and unmarked before reuse.
struct FileSlot {
  std::atomic<bool> held{false};
  char path[4096];
};
std::array<FileSlot, kMaxHeld> files;
std::array<std::atomic<pid_t>, kMaxHeld> children{};  // 0: free
std::atomic<bool> installed{false};

constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};

extern "C" void clean_up_and_die(int sig) {
  for (auto& c : children)
    if (const pid_t pid = c.load(); pid > 0) ::kill(pid, sig);
  for (FileSlot& s : files)
    if (s.held.load()) ::unlink(s.path);
  // The default action now (SA_RESETHAND restored it; SA_NODEFER lets it through at once), so the parent
  // sees the process end by this signal, as it would have without the handler.
  ::raise(sig);
}

void install_once() {
  if (installed.exchange(true)) return;
  for (int sig : kSignals) {
    struct sigaction now {};
    if (::sigaction(sig, nullptr, &now) != 0 || now.sa_handler != SIG_DFL) continue;
    struct sigaction act {};
    act.sa_handler = clean_up_and_die;
    sigemptyset(&act.sa_mask);
    act.sa_flags = SA_RESETHAND | SA_NODEFER;
    ::sigaction(sig, &act, nullptr);
  }
}

}  // namespace

TempFileHold::TempFileHold(const std::string& path) {
  std::error_code ec;
  const std::string full = std::filesystem::absolute(path, ec).string();
  if (ec || full.size() >= sizeof(FileSlot::path)) return;
  install_once();
  for (int k = 0; k < kMaxHeld; ++k) {
    FileSlot& s = files[static_cast<std::size_t>(k)];
    if (s.held.load()) continue;
    std::memcpy(s.path, full.c_str(), full.size() + 1);
    s.held.store(true);
    slot_ = k;
    return;
  }
}

void TempFileHold::release() {
  if (slot_ < 0) return;
  files[static_cast<std::size_t>(slot_)].held.store(false);
  slot_ = -1;
}

ChildHold::ChildHold(pid_t child) {
  if (child <= 0) return;
  install_once();
  for (int k = 0; k < kMaxHeld; ++k) {
    pid_t free = 0;
    if (children[static_cast<std::size_t>(k)].compare_exchange_strong(free, child)) {
      slot_ = k;
      return;
    }
  }
}

void ChildHold::release() {
  if (slot_ < 0) return;
  children[static_cast<std::size_t>(slot_)].store(0);
  slot_ = -1;
}

}  // namespace grainlab
