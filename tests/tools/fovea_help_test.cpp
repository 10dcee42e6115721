// `fovea` is the product: its --help lists exactly pointset, interpolate,
// reconstruct and render; the lab's commands (accuracy, motion, pricelist) are
// fovea-eval's and fovea refuses them. Runs the fovea binary built next to this
// test (both go to the build's bin/).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "../common/cli_help.hpp"

namespace {

using foveart::test::help_subcommands;
using foveart::test::HelpRun;

HelpRun run_fovea_for_help(const std::string& args) { return foveart::test::run_sibling_tool("fovea", args); }

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
