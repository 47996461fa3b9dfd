#include "plumage/common/progress.h"

#include <cstdio>
#include <unistd.h>

namespace plumage {
namespace {
std::atomic<bool> g_quiet{false};

std::string format_seconds(double s) {
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.1fs", s);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  return buf;
}
}  // namespace

void ProgressBar::set_quiet(bool q) { g_quiet = q; }

ProgressBar::ProgressBar(std::string label, std::uint64_t total, bool quiet)
    : label_(std::move(label)),
      total_(total),
      enabled_(!quiet && !g_quiet && ::isatty(STDERR_FILENO)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
  if (enabled_) draw(0, false);
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::advance(std::uint64_t n) {
  const std::uint64_t done = done_.fetch_add(n) + n;
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock lock(mu_, std::try_to_lock);
  if (!lock.owns_lock() || now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(done, false);
}

void ProgressBar::finish() {
  std::lock_guard lock(mu_);
  if (finished_) return;
  finished_ = true;
  if (enabled_) draw(done_.load(), true);
}

void ProgressBar::draw(std::uint64_t done, bool final_line) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total_ ? double(done) / double(total_) : 1.0;
  const int width = 30;
  const int filled = int(frac * width + 0.5);
  std::string bar(filled, '#');
  bar.resize(width, '.');
  std::string eta = frac > 0 && !final_line ? " ETA " + format_seconds(elapsed * (1 - frac) / frac) : "";
  std::fprintf(stderr, "\r%s [%s] %3d%% %s%s%s", label_.c_str(), bar.c_str(), int(frac * 100 + 0.5),
               format_seconds(elapsed).c_str(), eta.c_str(), final_line ? "\n" : "   ");
  std::fflush(stderr);
}

}  // namespace plumage
