// SIGINT and SIGTERM: recorded, then acted on at the next checkpoint, or by the
// handler itself as a last resort (interrupt.h).
#include "plumage/common/interrupt.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>

namespace plumage {
namespace {

constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;
enum SlotState : int { kFree = 0, kBusy = 1, kFile = 2, kFolder = 3 };
struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};
std::array<Slot, kSlots> g_slots;
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "the handler reads atomics");

// Only async-signal-safe calls from here (write, unlink, rmdir, _exit).
[[noreturn]] void last_resort(int sig) {
  const char* line = sig == SIGINT    ? "plumage: interrupted by SIGINT: stopped at once, its temporary files removed\n"
                     : sig == SIGTERM ? "plumage: interrupted by SIGTERM: stopped at once, its temporary files removed\n"
                                      : "plumage: interrupted by a signal: stopped at once, its temporary files removed\n";
  [[maybe_unused]] const ssize_t written = ::write(2, line, std::strlen(line));
  for (Slot& s : g_slots)
    if (s.state.load() == kFile) ::unlink(s.path);
  for (auto it = g_slots.rbegin(); it != g_slots.rend(); ++it)  // deepest (latest) folder first
    if (it->state.load() == kFolder) ::rmdir(it->path);
  ::_exit(128 + sig);
}

extern "C" void on_stop_signal(int sig) {
  int none = 0;
  if (g_signal.compare_exchange_strong(none, sig)) {
    ::alarm(kInterruptGraceSeconds);  // the run has this long to reach a checkpoint
    return;
  }
  last_resort(g_signal.load());  // a second signal: stop now
}

extern "C" void on_alarm(int) {
  if (const int sig = g_signal.load()) last_resort(sig);
}

void install(int sig, void (*handler)(int)) {
  struct sigaction old {};
  ::sigaction(sig, nullptr, &old);
  if (old.sa_handler == SIG_IGN) return;  // started ignoring it (nohup): keep ignoring it
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  ::sigaction(sig, &sa, nullptr);
}

std::string signal_name(int sig) {
  if (sig == SIGINT) return "SIGINT";
  if (sig == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(sig);
}

}  // namespace

Interrupted::Interrupted(int signal) : signal_(signal), what_("interrupted by " + signal_name(signal)) {}

void install_interrupt_handlers() {
  install(SIGINT, on_stop_signal);
  install(SIGTERM, on_stop_signal);
  install(SIGALRM, on_alarm);
}

int interrupt_signal() { return g_signal.load(std::memory_order_relaxed); }

void check_interrupted() {
  if (const int sig = interrupt_signal()) throw Interrupted(sig);
}

RemovedOnSignal::RemovedOnSignal(const std::filesystem::path& path, bool folder) {
  const std::string& s = path.native();
  if (s.size() >= kPathBytes) return;
  for (int i = 0; i < kSlots; ++i) {
    int free = kFree;
    if (!g_slots[i].state.compare_exchange_strong(free, kBusy)) continue;
    std::memcpy(g_slots[i].path, s.c_str(), s.size() + 1);
    g_slots[i].state.store(folder ? kFolder : kFile);
    slot_ = i;
    return;
  }
}

RemovedOnSignal::~RemovedOnSignal() {
  if (slot_ >= 0) g_slots[slot_].state.store(kFree);
}

RemovedOnSignal& RemovedOnSignal::operator=(RemovedOnSignal&& other) noexcept {
  if (this != &other) {
    if (slot_ >= 0) g_slots[slot_].state.store(kFree);
    slot_ = other.slot_;
    other.slot_ = -1;
  }
  return *this;
}

}  // namespace plumage
