#include "temp_files.hpp"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstring>
#include <filesystem>

namespace grainlab {

namespace {

// Fixed slots, so the handler reads only memory that never moves and calls only unlink, sigaction and
// raise (async-signal-safe). A slot's path is written before it is marked held and unmarked before reuse.
struct Slot {
  std::atomic<bool> held{false};
  char path[4096];
};
std::array<Slot, TempFileHold::kMaxHeld> slots;
std::atomic<bool> installed{false};

constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_held_and_die(int sig) {
  for (Slot& s : slots)
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
    act.sa_handler = remove_held_and_die;
    sigemptyset(&act.sa_mask);
    act.sa_flags = SA_RESETHAND | SA_NODEFER;
    ::sigaction(sig, &act, nullptr);
  }
}

}  // namespace

TempFileHold::TempFileHold(const std::string& path) {
  std::error_code ec;
  const std::string full = std::filesystem::absolute(path, ec).string();
  if (ec || full.size() >= sizeof(Slot::path)) return;
  install_once();
  for (int k = 0; k < kMaxHeld; ++k) {
    Slot& s = slots[static_cast<std::size_t>(k)];
    if (s.held.load()) continue;
    std::memcpy(s.path, full.c_str(), full.size() + 1);
    s.held.store(true);
    slot_ = k;
    return;
  }
}

void TempFileHold::release() {
  if (slot_ < 0) return;
  slots[static_cast<std::size_t>(slot_)].held.store(false);
  slot_ = -1;
}

}  // namespace grainlab
