// Runs a command-line tool built next to the test binary (both go to the
// build's bin/) and reads the subcommands its CLI11 --help lists.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

namespace foveart::test {

struct HelpRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// `tool` from this test binary's directory with `args`; exit_code -1 when it is missing.
inline HelpRun run_sibling_tool(const std::string& tool, const std::string& args) {
  const std::filesystem::path path = std::filesystem::read_symlink("/proc/self/exe").parent_path() / tool;
  HelpRun r;
  if (!std::filesystem::exists(path)) {
    r.output = path.string() + " is missing: build the " + tool + " target";
    return r;
  }
  const std::string cmd = "'" + path.string() + "' " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr) r.output += buf;
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// The names under "Subcommands:" in CLI11's help.
inline std::set<std::string> help_subcommands(const std::string& help) {
  std::set<std::string> names;
  std::istringstream in(help);
  bool listing = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Subcommands:", 0) == 0) {
      listing = true;
      continue;
    }
    if (!listing) continue;
    std::istringstream words(line);
    std::string name;
    if (line.rfind("  ", 0) == 0 && (words >> name)) names.insert(name);
  }
  return names;
}

}  // namespace foveart::test
