#pragma once
// Subcommand registry: each apps/<name>.cpp registers one subcommand with a
// static `plumage::cli::Registration`, so adding a command touches one file.
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace plumage::cli {

// Adds options to `sub` (binding them to state the closure owns) and returns the
// function that runs the command; it returns the process exit code.
using Setup = std::function<std::function<int()>(CLI::App& sub)>;

struct CommandSpec {
  std::string name;
  std::string description;
  Setup setup;
};

std::vector<CommandSpec>& commands();

struct Registration {
  Registration(std::string name, std::string description, Setup setup) {
    commands().push_back({std::move(name), std::move(description), std::move(setup)});
  }
};

// A command line that cannot work although each value on it is valid: options
// that contradict each other or that do not apply to what was asked. A command
// throws it before it reads or writes any file; it exits 2 like a parse error.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Options every command shares (set before the command runs).
struct GlobalOptions {
  bool quiet = false;
  bool stats = false;
};
const GlobalOptions& global_options();

}  // namespace plumage::cli
