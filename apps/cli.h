#pragma once
// The command line as a function, so that main() and the argument-vector fuzzer
// (tests/fuzz/fuzz_argv.cpp) go through the same parsing.
#include <functional>

namespace plumage::cli {

// Builds every subcommand's options and parses `argv`. Returns -1 with `run` set
// to the command to run when it parsed; otherwise the exit status, after printing
// the help, the version, or the one-line usage error (2).
int parse_command_line(int argc, const char* const* argv, std::function<int()>& run);

// parse_command_line, then the command; plumage::Error and other exceptions
// become one `plumage: error:` line and exit status 1.
int run_command_line(int argc, const char* const* argv);

}  // namespace plumage::cli
