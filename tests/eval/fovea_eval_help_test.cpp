// `fovea-eval` is the lab: its --help lists accuracy, motion, pricelist and
// bench-md, and none of the product's commands (pointset, interpolate,
// reconstruct, render). Runs the fovea-eval binary built next to this
// test (both go to the build's bin/).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct HelpRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

HelpRun run_fovea_eval(const std::string& args) {
  const fs::path fovea = fs::read_symlink("/proc/self/exe").parent_path() / "fovea-eval";
  HelpRun r;
  if (!fs::exists(fovea)) {
    r.output = fovea.string() + " is missing: build the fovea-eval target";
    return r;
  }
  const std::string cmd = "'" + fovea.string() + "' " + args + " 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr) r.output += buf;
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// The names under "Subcommands:" in CLI11's help.
std::set<std::string> help_subcommands(const std::string& help) {
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

}  // namespace

TEST(FoveaEvalHelp, ListsTheLabsCommands) {
  const HelpRun r = run_fovea_eval("--help");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(help_subcommands(r.output), (std::set<std::string>{"accuracy", "motion", "pricelist", "bench-md"})) << r.output;
}
