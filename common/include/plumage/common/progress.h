#pragma once
// A progress bar on stderr with elapsed time and ETA. Silent when stderr is not
// a terminal or when quiet; thread-safe `advance`.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace plumage {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::uint64_t total, bool quiet = false);
  ~ProgressBar();  // finishes the line
  void advance(std::uint64_t n = 1);
  void finish();
  bool enabled() const { return enabled_; }

  // Global switch set by the CLI's --quiet.
  static void set_quiet(bool q);

 private:
  void draw(std::uint64_t done, bool final_line);
  std::string label_;
  std::uint64_t total_;
  std::atomic<std::uint64_t> done_{0};
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
  std::mutex mu_;
};

}  // namespace plumage
