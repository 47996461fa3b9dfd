// Fuzzes the command line itself (apps/cli.h): the input, split at newlines, is
// the argument vector after `plumage`. Every vector either parses into a command
// (which is not run: that would read and write files) or is answered with the
// help, the version or a one-line usage error (exit 2); an exception, a crash or
// a sanitizer report is a finding. This covers every subcommand's options and
// every validator of apps/option_checks.h.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "fuzz_verdict.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static std::ostringstream sink;  // help texts and error lines, not the fuzzer's log
  static const bool quiet = [] {
    std::cout.rdbuf(sink.rdbuf());
    std::cerr.rdbuf(sink.rdbuf());
    return true;
  }();
  (void)quiet;
  sink.str("");

  std::vector<std::string> args{"plumage"};
  std::string current;
  for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
    if (data[i] == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current += char(data[i]);
    }
  }
  if (!current.empty()) args.push_back(current);
  std::vector<const char*> argv;
  for (const auto& a : args) argv.push_back(a.c_str());
  argv.push_back(nullptr);

  plumage::fuzz::expect_parse_or_error([&] {
    std::function<int()> run;
    const int rc = plumage::cli::parse_command_line(int(args.size()), argv.data(), run);
    plumage::fuzz::check(rc == -1 || rc == 0 || rc == 2, "parse_command_line returned an undocumented status");
    plumage::fuzz::check(rc != -1 || bool(run), "a command parsed but nothing would run");
  });
  return 0;
}
