// `fovea-eval` is the lab: its --help lists accuracy, motion, pricelist and
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
  EXPECT_EQ(help_subcommands(r.output), (std::set<std::string>{"accuracy", "motion", "pricelist", "bench-md"}))
      << r.output;
}
