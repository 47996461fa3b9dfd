// SIGINT and SIGTERM stop a run and leave nothing behind (interrupt.h,
// docs/robustness.md "Signals"): the run exits 128 + signal, its temporary files
// are gone, no output it had not finished is there, and a folder it created is
// removed. Signals are sent at several points of a run, from start-up to the
// write of its output.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "plumage/common/interrupt.h"

namespace fs = std::filesystem;
using plumage::kInterruptGraceSeconds;
using plumage::test::fresh_test_dir;
using plumage::test::plumage_cli;
using plumage::test::spawn_plumage;

namespace {

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir)) names.insert(fs::relative(e.path(), dir).string());
  return names;
}

struct Stopped {
  int status = 0;        // waitpid's
  double seconds = 0;    // from the start to the end of the run
  std::string err;       // what it printed on stderr
};

// Whether process `pid` has a handler for `sig` (Linux: /proc/PID/status's SigCgt
// mask), i.e. is past its start-up.
bool catches(pid_t pid, int sig) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1;
  return false;
}

// Runs `plumage ARGS` and sends each of `signals` `after` seconds from the start
// (one after the other, 50 ms apart), then waits for it. With `after` > 0 the
// seconds count from when it has installed its handlers (a sanitizer build takes
// half a second to reach main); at 0 the signal meets its start-up.
Stopped run_and_signal(const std::vector<std::string>& args, const std::vector<int>& signals, double after,
                       const fs::path& err_file) {
  const auto t0 = std::chrono::steady_clock::now();
  Stopped r;
  const pid_t pid = spawn_plumage(args, err_file);
  if (pid < 0) {
    r.status = -1;
    return r;
  }
  if (after > 0 && !signals.empty())
    for (int k = 0; k < 2000 && !catches(pid, signals.front()); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::duration<double>(after));
  for (const int sig : signals) {
    ::kill(pid, sig);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::waitpid(pid, &r.status, 0);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::stringstream s;
  s << std::ifstream(err_file).rdbuf();
  r.err = s.str();
  return r;
}

// Stopped by `sig`: exit 128 + sig with a one-line message (also when it came
// after the last checkpoint, the outputs complete), or, `at_start_up`, possibly
// killed by it before the handlers were installed.
void expect_stopped_by(const Stopped& r, int sig, bool at_start_up = false) {
  if (at_start_up && WIFSIGNALED(r.status)) {
    EXPECT_EQ(WTERMSIG(r.status), sig);
    return;
  }
  ASSERT_TRUE(WIFEXITED(r.status)) << r.err;
  EXPECT_EQ(WEXITSTATUS(r.status), 128 + sig) << r.err;
  const std::string name = sig == SIGINT ? "SIGINT" : "SIGTERM";
  EXPECT_NE(r.err.find("interrupted by " + name), std::string::npos) << r.err;
}

}  // namespace

TEST(Signals, ARenderStoppedAnywhereLeavesNoTemporaryAndNoPartialImage) {
  const fs::path dir = fresh_test_dir("signal_render");
  const fs::path curves = dir / "f.fcurves";
  ASSERT_EQ(plumage_cli("-q generate --preset osprey-wing-covert -o '" + curves.string() + "'").rc, 0);
  const std::vector<std::string> args{"-q", "render", curves.string(), "--spp", "16", "--resolution", "240x360",
                                      "--threads", "2", "-o", (dir / "out.png").string()};
  // How long the whole run takes, to signal it at fractions of that.
  const fs::path err = fs::temp_directory_path() / ("plumage_signal_err_" + std::to_string(::getpid()) + ".txt");
  const Stopped whole = run_and_signal(args, {}, 0.0, err);
  ASSERT_TRUE(WIFEXITED(whole.status) && WEXITSTATUS(whole.status) == 0) << whole.err;
  ASSERT_TRUE(fs::exists(dir / "out.png"));
  fs::remove(dir / "out.png");
  const std::set<std::string> before = names_in(dir);
  int stopped_early = 0;
  const std::vector<std::pair<int, double>> when{{SIGINT, 0.0},  {SIGINT, 0.3},  {SIGINT, 0.6},
                                                 {SIGINT, 0.9},  {SIGTERM, 0.1}, {SIGTERM, 0.5},
                                                 {SIGTERM, 0.85}};
  for (const auto& [sig, fraction] : when) {
    SCOPED_TRACE(std::string(sig == SIGINT ? "SIGINT" : "SIGTERM") + " at " + std::to_string(fraction) +
                 " of the run");
    const Stopped r = run_and_signal(args, {sig}, fraction * whole.seconds, err);
    // Finished before the signal came (the run's time varies with the machine's
    // load), or stopped by it; never a temporary, never a partial image.
    const bool finished = WIFEXITED(r.status) && WEXITSTATUS(r.status) == 0;
    if (!finished) expect_stopped_by(r, sig, fraction == 0.0);
    std::set<std::string> after = names_in(dir);
    if (after.count("out.png")) {
      EXPECT_GT(fs::file_size(dir / "out.png"), 1000u);
      fs::remove(dir / "out.png");
      after.erase("out.png");
    } else {
      EXPECT_FALSE(finished);
      ++stopped_early;
      // Stopped at a checkpoint (or by the handler after its grace), not run to its end.
      EXPECT_LT(r.seconds, fraction * whole.seconds + kInterruptGraceSeconds + 1.0) << r.err;
    }
    EXPECT_EQ(after, before);
  }
  EXPECT_GE(stopped_early, 4);  // the signals up to 60 % of the run stopped it before its image
  fs::remove(err);
  fs::remove_all(dir);
}

TEST(Signals, ASecondSignalStopsAtOnceAndLeavesNoTemporary) {
  const fs::path dir = fresh_test_dir("signal_twice");
  const fs::path curves = dir / "f.fcurves";
  ASSERT_EQ(plumage_cli("-q generate --preset osprey-wing-covert -o '" + curves.string() + "'").rc, 0);
  const std::set<std::string> before = names_in(dir);
  const fs::path err = fs::temp_directory_path() / ("plumage_signal_err2_" + std::to_string(::getpid()) + ".txt");
  const Stopped r = run_and_signal({"-q", "render", curves.string(), "--spp", "256", "--resolution", "240x360", "-o",
                                    (dir / "out.png").string()},
                                   {SIGINT, SIGINT}, 0.5, err);
  expect_stopped_by(r, SIGINT);
  EXPECT_EQ(names_in(dir), before);
  fs::remove(err);
  fs::remove_all(dir);
}

TEST(Signals, PhotoToFeatherStoppedRemovesTheFolderItCreated) {
  const fs::path photo = fs::path(PLUMAGE_SHARED_DIR) / "photos" / "pink-contour-feather.jpg";
  if (!fs::exists(photo)) GTEST_SKIP() << "shared photos absent";
  const fs::path dir = fresh_test_dir("signal_p2f");
  const fs::path err = fs::temp_directory_path() / ("plumage_signal_err3_" + std::to_string(::getpid()) + ".txt");
  for (const double after : {0.3, 2.0, 5.0}) {
    SCOPED_TRACE("SIGTERM after " + std::to_string(after) + " s");
    const fs::path out = dir / "run";
    const Stopped r = run_and_signal({"-q", "photo-to-feather", photo.string(), "--threads", "2", "-o", out.string()},
                                     {SIGTERM}, after, err);
    expect_stopped_by(r, SIGTERM);
    EXPECT_FALSE(fs::exists(out)) << "the folder the run created is still there";
    EXPECT_TRUE(names_in(dir).empty());
    fs::remove_all(out);
  }
  fs::remove(err);
  fs::remove_all(dir);
}
