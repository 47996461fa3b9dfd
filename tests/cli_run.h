#pragma once
// Runs the built `plumage` binary (PLUMAGE_CLI) with arguments (a shell command
// line: redirections and quotes work) and captures its exit code and output.
// Shared by the CLI tests.
#include <unistd.h>
#include <sys/wait.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace plumage::test
