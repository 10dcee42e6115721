// `fovea-eval` is the lab: its --help lists accuracy, density, motion, pricelist, perceptual and
// bench-md, and none of the product's commands (pointset, interpolate,
// reconstruct, render). Runs the fovea-eval binary built next to this
// test (both go to the build's bin/).
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "../common/cli_help.hpp"

namespace {

using foveart::test::help_subcommands;
using foveart::test::HelpRun;

HelpRun run_fovea_eval(const std::string& args) { return foveart::test::run_sibling_tool("fovea-eval", args); }

}  // namespace

TEST(FoveaEvalHelp, ListsTheLabsCommands) {
  const HelpRun r = run_fovea_eval("--help");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(help_subcommands(r.output),
            (std::set<std::string>{"accuracy", "density", "motion", "pricelist", "perceptual", "bench-md"}))
      << r.output;
}

TEST(FoveaEvalHelp, PerceptualBadArgumentsExitTwoWithTheirMessage) {
  HelpRun r = run_fovea_eval("perceptual --gaze 1,1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--test A and --reference B are required"), std::string::npos) << r.output;
  r = run_fovea_eval("perceptual --test /nonexistent/a.pfm --reference /nonexistent/b.pfm --gaze 1,1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--test: "), std::string::npos) << r.output;
}
