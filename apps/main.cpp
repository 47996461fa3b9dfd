// plumage: photo -> feather curves -> renders. One subcommand per apps/*.cpp;
// the command line itself is apps/cli.cpp.
#include "cli.h"

int main(int argc, char** argv) { return plumage::cli::run_command_line(argc, argv); }
