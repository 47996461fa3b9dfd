#pragma once
// Stopping on SIGINT and SIGTERM without debris (docs/robustness.md, "Signals").
//
// The first signal is only recorded: the run stops at its next checkpoint
// (check_interrupted: every render tile, far-field bin and progress step), where
// Interrupted is thrown and unwinds it, so every FileBatch removes its temporary
// files, photo-to-feather removes a folder it created, and the CLI exits
// 128 + signal (130 for SIGINT, 143 for SIGTERM). If no checkpoint comes within
// kInterruptGraceSeconds, or a second signal arrives, the handler stops the run
// itself: it removes the temporaries that are registered (RemovedOnSignal), and
// the folders the run created where they are empty, and exits at once with the
// same code.
#include <exception>
#include <filesystem>
#include <string>

namespace plumage {

inline constexpr unsigned kInterruptGraceSeconds = 3;

class Interrupted : public std::exception {
 public:
  explicit Interrupted(int signal);
  int signal() const { return signal_; }
  int exit_code() const { return 128 + signal_; }
  // "interrupted by SIGINT"
  const char* what() const noexcept override { return what_.c_str(); }

 private:
  int signal_;
  std::string what_;
};

// Installs the handlers for SIGINT and SIGTERM (the CLI's run does, once).
void install_interrupt_handlers();
// The signal that asked the run to stop, or 0.
int interrupt_signal();
// Throws Interrupted when a signal asked the run to stop.
void check_interrupted();

// While one lives, the handler's last resort removes `path`: a temporary file
// (unlinked), or with `folder` a folder the run created (removed when empty).
// Paths longer than the handler's slots hold (4095 bytes), and more than 64 at
// once, are not registered; they are still removed on the orderly path.
class RemovedOnSignal {
 public:
  RemovedOnSignal() = default;
  explicit RemovedOnSignal(const std::filesystem::path& path, bool folder = false);
  ~RemovedOnSignal();
  RemovedOnSignal(RemovedOnSignal&& other) noexcept : slot_(other.slot_) { other.slot_ = -1; }
  RemovedOnSignal& operator=(RemovedOnSignal&& other) noexcept;
  RemovedOnSignal(const RemovedOnSignal&) = delete;
  RemovedOnSignal& operator=(const RemovedOnSignal&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace plumage
