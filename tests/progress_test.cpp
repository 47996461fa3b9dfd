// The progress bar (progress.h) writes only to a terminal, never into a log file
// or a pipe, and never with --quiet.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include "plumage/common/atomic_file.h"
#include "plumage/common/progress.h"

using namespace plumage;
namespace fs = std::filesystem;

namespace {

// Points file descriptor 2 at `fd` for the scope, then restores the original stderr.
class StderrRedirect {
 public:
  explicit StderrRedirect(int fd) {
    std::fflush(stderr);
    saved_ = ::dup(STDERR_FILENO);
    ::dup2(fd, STDERR_FILENO);
  }
  ~StderrRedirect() {
    std::fflush(stderr);
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
  }

 private:
  int saved_;
};

void run_bar(bool quiet) {
  ProgressBar bar("working", 1000, quiet);
  for (int i = 0; i < 1000; ++i) bar.advance();
  bar.finish();
}

}  // namespace

TEST(ProgressBar, SilentWhenStderrIsAFile) {
  const fs::path log =
      fs::temp_directory_path() / ("plumage_progress_" + std::to_string(::getpid()) + ".log");
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ASSERT_GE(fd, 0);
  bool enabled = true;
  {
    StderrRedirect redirect(fd);
    ProgressBar bar("working", 10);
    enabled = bar.enabled();
    for (int i = 0; i < 10; ++i) bar.advance();
  }  // the destructor finishes the bar: still nothing may be written
  ::close(fd);
  EXPECT_FALSE(enabled);
  EXPECT_EQ(read_file(log), "");
  fs::remove(log);
}

TEST(ProgressBar, SilentWhenStderrIsAPipe) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  {
    StderrRedirect redirect(fds[1]);
    run_bar(false);
  }
  ::close(fds[1]);
  char buf[16];
  EXPECT_EQ(::read(fds[0], buf, sizeof buf), 0);  // end of file: nothing written
  ::close(fds[0]);
}

// The other side of the contract: on a terminal it does draw, and --quiet (the
// global switch) or the constructor's flag silence it. Without this the silent
// tests above would also pass for a bar that never draws at all.
TEST(ProgressBar, DrawsOnATerminalUnlessQuiet) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || ::grantpt(master) != 0 || ::unlockpt(master) != 0)
    GTEST_SKIP() << "no pseudo-terminals here";
  const int slave = ::open(::ptsname(master), O_RDWR | O_NOCTTY);
  ASSERT_GE(slave, 0);
  auto drain = [&] {
    std::string out;
    char buf[4096];
    pollfd p{master, POLLIN, 0};
    while (::poll(&p, 1, 100) > 0 && (p.revents & POLLIN)) {
      const ssize_t n = ::read(master, buf, sizeof buf);
      if (n <= 0) break;
      out.append(buf, std::size_t(n));
    }
    return out;
  };
  {
    StderrRedirect redirect(slave);
    run_bar(false);
  }
  const std::string drawn = drain();
  EXPECT_NE(drawn.find("working"), std::string::npos) << drawn;
  EXPECT_NE(drawn.find("100%"), std::string::npos) << drawn;
  {
    StderrRedirect redirect(slave);
    run_bar(true);
    ProgressBar::set_quiet(true);
    run_bar(false);
    ProgressBar::set_quiet(false);
  }
  EXPECT_EQ(drain(), "");
  ::close(slave);
  ::close(master);
}
