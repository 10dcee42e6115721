// The one way a FoveaRT command-line tool runs its CLI11 app: parse errors print
// CLI11's message and exit code; any other error escaping a subcommand prints
// "<tool> <subcommand>: error: <what>" and returns 1. Nothing escapes main. It records
// the command line for the result files a subcommand writes (toolkit/machine.hpp).
#pragma once

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include <toolkit/machine.hpp>

namespace foveart::toolkit {

inline int run_cli(CLI::App& app, int argc, char** argv, const char* tool) {
  set_command_line(argc, argv);  // for the result files a command writes
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    const auto subs = app.get_subcommands();
    std::fprintf(stderr, "%s %s: error: %s\n", tool, subs.empty() ? "" : subs.front()->get_name().c_str(), e.what());
    return 1;
  }
  return 0;
}

}  // namespace foveart::toolkit
