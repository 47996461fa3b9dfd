#pragma once
// Runs the built `plumage` binary (PLUMAGE_CLI) with arguments (a shell command
// line: redirections and quotes work) and captures its exit code and output.
// Shared by the CLI tests.
#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>
#include <sys/wait.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace plumage::test {

struct CliResult {
  int rc;
  std::string output;  // stdout and stderr
};

// What a run printed on each stream, for tests that tell them apart.
struct CliStreams {
  int rc;
  std::string out, err;
};

namespace detail {
// Runs `plumage ARGS` with `redirect` appended and returns the exit code and stdout.
inline int run_plumage(const std::string& args, const std::string& redirect, std::string& out) {
  const std::string cmd = std::string("'") + PLUMAGE_CLI + "' " + args + " " + redirect;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) {
    out = "popen failed";
    return -1;
  }
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace detail

inline CliResult plumage_cli(const std::string& args) {
  CliResult r{0, {}};
  r.rc = detail::run_plumage(args, "2>&1", r.output);
  return r;
}

// stderr goes through a file of this process's own (ctest -j2 runs tests in parallel).
inline CliStreams plumage_cli_streams(const std::string& args) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path err_file =
      std::filesystem::temp_directory_path() /
      ("plumage_cli_stderr_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".txt");
  CliStreams r{0, {}, {}};
  r.rc = detail::run_plumage(args, "2>'" + err_file.string() + "'", r.out);
  std::stringstream err;
  err << std::ifstream(err_file).rdbuf();
  r.err = err.str();
  std::error_code ec;
  std::filesystem::remove(err_file, ec);
  return r;
}

// A fresh, empty folder for one test of this process (ctest -j runs tests side by side).
inline std::filesystem::path fresh_test_dir(const std::string& name) {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("plumage_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

// Starts `plumage ARGS` as a child of its own (no shell between, so a signal or
// wait4 reaches plumage itself), stdout to /dev/null and stderr to `err_file`.
// Returns its pid, or -1 when it could not be started.
inline pid_t spawn_plumage(const std::vector<std::string>& args, const std::filesystem::path& err_file) {
  std::vector<std::string> all{PLUMAGE_CLI};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  // The child starts with SIGINT, SIGQUIT and SIGTERM at their defaults, so it
  // installs its handlers however this test was started: a shell runs a
  // background command (scripts/sanitize.sh's shards) with SIGINT and SIGQUIT
  // ignored, and a program keeps a signal ignored at start ignored.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t defaults;
  sigemptyset(&defaults);
  for (const int sig : {SIGINT, SIGQUIT, SIGTERM}) sigaddset(&defaults, sig);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  sigset_t none;
  sigemptyset(&none);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, PLUMAGE_CLI, &actions, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

}  // namespace plumage::test
