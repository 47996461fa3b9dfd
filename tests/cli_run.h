#pragma once
// Runs the built `plumage` binary (PLUMAGE_CLI) with arguments and captures its
// exit code and its stdout and stderr together. Shared by the CLI tests.
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace plumage::test {

struct CliResult {
  int rc;
  std::string output;  // stdout and stderr
};

inline CliResult plumage_cli(const std::string& args) {
  const std::string cmd = std::string(PLUMAGE_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string out;
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

}  // namespace plumage::test
