#include "cli.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <memory>
#include <new>
#include <unistd.h>

#include "command.h"
#include "option_checks.h"
#include "plumage/common/atomic_file.h"
#include "plumage/common/error.h"
#include "plumage/common/install.h"
#include "plumage/common/interrupt.h"
#include "plumage/common/progress.h"
#include "plumage/common/stats.h"
#include "plumage/common/text.h"

namespace plumage::cli {

std::vector<CommandSpec>& commands() {
  static std::vector<CommandSpec> c;
  return c;
}

namespace {
GlobalOptions g_options;
std::string g_command;  // the subcommand parsed, for the usage error's hint
}
const GlobalOptions& global_options() { return g_options; }

int parse_command_line(int argc, const char* const* argv, std::function<int()>& run) {
  CLI::App app{
      "Plumage: model and render bird feathers from photos (Baron et al. 2021, "
      "\"Microstructure-based appearance rendering for feathers\").\n"
      "Pipeline: analyze (photo -> layout.json) -> generate (-> feather.fcurves) -> render.\n"
      "Run `plumage COMMAND --help` for a command's options."};
  app.set_version_flag("--version", version_text());
  app.require_subcommand(1);
  app.fallthrough();
  g_options = GlobalOptions{};
  app.add_flag("-q,--quiet", g_options.quiet, "No progress bars");
  app.add_flag("--stats", g_options.stats, "Print statistics counters at the end");

  auto& specs = commands();
  std::sort(specs.begin(), specs.end(), [](auto& a, auto& b) { return a.name < b.name; });
  run = nullptr;
  for (auto& spec : specs) {
    CLI::App* sub = app.add_subcommand(spec.name, spec.description);
    auto fn = std::make_shared<std::function<int()>>(spec.setup(*sub));
    sub->callback([fn, &run, name = spec.name] {
      run = *fn;
      g_command = name;
    });
  }
  check_option_types(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    std::string help = "plumage --help";  // or the help of the subcommand that was parsed
    const CLI::App* parsed = nullptr;
    for (const CLI::App* sub : app.get_subcommands()) parsed = sub;
    if (parsed) help = "plumage " + parsed->get_name() + " --help";
    // CLI11 checks required values before it reports what it did not know, so a
    // misspelt command or option would read "A subcommand is required" or
    // "input is required": name the word it did not know instead.
    std::string message = e.what();
    const std::vector<std::string> extras = app.remaining(true);
    if (dynamic_cast<const CLI::RequiredError*>(&e) && !extras.empty()) {
      if (parsed) {
        if (extras[0].rfind('-', 0) == 0) message = "unknown option " + extras[0];
      } else if (extras[0].rfind('-', 0) != 0) {
        message = "unknown command '" + extras[0] + "'; the commands are";
        for (std::size_t i = 0; i < specs.size(); ++i) message += (i ? ", " : " ") + specs[i].name;
      }
    }
    std::cerr << "plumage: error: " << printable(message) << " (see `" << help << "`)\n";
    return 2;
  }
  return -1;
}

namespace {
// What went to stdout (info, --json, --print-params, --help) must have arrived: a
// full disk or a closed stream is an error (exit 1), not a silent success.
int stdout_checked(int rc) {
  errno = 0;
  std::cout.flush();
  if (std::cout) return rc;
  const int err = errno;
  std::cerr << "plumage: error: cannot write to standard output: "
            << (err ? std::strerror(err) : "the stream is closed or full") << "\n";
  return rc == 0 ? 1 : rc;
}
}  // namespace

int run_command_line(int argc, const char* const* argv) {
  install_interrupt_handlers();  // SIGINT, SIGTERM: stop, leave nothing behind (interrupt.h)
  std::function<int()> run;
  if (const int rc = parse_command_line(argc, argv, run); rc >= 0) return stdout_checked(rc);
  ProgressBar::set_quiet(g_options.quiet);
  const InputsProtected protect_inputs;  // no output of this run replaces what it reads
  try {
    const int rc = run ? run() : 0;
    if (g_options.stats) stats_print(std::cerr);
    // A signal after the last checkpoint: the outputs are complete, but a script
    // looping over photos must still see that it was asked to stop.
    check_interrupted();
    return stdout_checked(rc);
  } catch (const Interrupted& e) {
    // Unwound: every staged output's temporary is gone, a folder the run made too.
    ::alarm(0);
    std::cerr << "plumage: " << e.what() << ": stopped, its temporary files removed\n";
    return e.exit_code();
  } catch (const UsageError& e) {
    std::cerr << "plumage: error: " << printable(e.what()) << " (see `plumage " << g_command << " --help`)\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "plumage: error: out of memory: this run needs more than the machine can give; use a smaller "
                 "--resolution, --spp or photo (docs/robustness.md)\n";
    return 1;
  } catch (const std::exception& e) {  // plumage::Error and the rest: one line, valid text
    std::cerr << "plumage: error: " << printable(e.what()) << "\n";
    return 1;
  }
}

}  // namespace plumage::cli
