// `fovea` is the product: its --help lists exactly pointset, interpolate,
// reconstruct and render; the lab's commands (accuracy, motion, pricelist) are
// fovea-eval's and fovea refuses them. Runs the fovea binary built next to this
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

HelpRun run_fovea_for_help(const std::string& args) {
  const fs::path fovea = fs::read_symlink("/proc/self/exe").parent_path() / "fovea";
  HelpRun r;
  if (!fs::exists(fovea)) {
    r.output = fovea.string() + " is missing: build the fovea target";
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

TEST(FoveaHelp, ListsExactlyTheFourProductCommands) {
  const HelpRun r = run_fovea_for_help("--help");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(help_subcommands(r.output), (std::set<std::string>{"pointset", "interpolate", "reconstruct", "render"}))
      << r.output;
}

TEST(FoveaHelp, TheLabsCommandsAreNotTheProducts) {
  for (const char* lab : {"pricelist", "accuracy", "motion", "bench-md"}) {
    const HelpRun r = run_fovea_for_help(lab);
    EXPECT_NE(r.exit_code, 0) << lab << ": " << r.output;
    EXPECT_NE(r.output.find(lab), std::string::npos) << "the message names it: " << r.output;
  }
}
