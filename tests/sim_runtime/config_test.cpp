// The runtime's FOVEART_SIM_* parsing (config_from_environment), motion variables first.
#include "config.h"

#include <gtest/gtest.h>

#include "sim_test_env.h"

namespace foveart::sim {
namespace {

TEST(SimConfig, MotionIsOffByDefaultWithSeedOne) {
  test::clear_sim_env();
  std::string error;
  const auto c = config_from_environment(&error);
  ASSERT_TRUE(c.has_value()) << error;
  EXPECT_TRUE(c->motion.empty());
  EXPECT_EQ(c->motion_seed, 1u);
}

TEST(SimConfig, ReadsTheMotionAndItsSeedNextToHeadAndGaze) {
  test::clear_sim_env();
  test::set_env({{"FOVEART_SIM_MOTION", "builtin"},
                 {"FOVEART_SIM_MOTION_SEED", "7"},
                 {"FOVEART_SIM_HEAD", "sway"},
                 {"FOVEART_SIM_GAZE", "/tmp/trace.csv"}});
  std::string error;
  const auto c = config_from_environment(&error);
  ASSERT_TRUE(c.has_value()) << error;
  EXPECT_EQ(c->motion, "builtin");
  EXPECT_EQ(c->motion_seed, 7u);
  // Both are still read (and checked); the runtime lets the motion override them.
  EXPECT_TRUE(c->head_sway);
  EXPECT_EQ(c->gaze_file, "/tmp/trace.csv");
  test::set_env({{"FOVEART_SIM_MOTION", "/data/walk.csv"}});
  EXPECT_EQ(config_from_environment(&error)->motion, "/data/walk.csv");
}

TEST(SimConfig, MalformedSeedIsAnErrorNamingTheVariable) {
  for (const char* seed : {"-1", "one", "1.5", "99999999999999999999999"}) {
    test::clear_sim_env();
    test::set_env({{"FOVEART_SIM_MOTION", "builtin"}, {"FOVEART_SIM_MOTION_SEED", seed}});
    std::string error;
    EXPECT_FALSE(config_from_environment(&error).has_value()) << seed;
    EXPECT_EQ(error, std::string("FOVEART_SIM_MOTION_SEED='") + seed + "' is not valid: expected an integer seed >= 0");
  }
  test::clear_sim_env();
}

}  // namespace
}  // namespace foveart::sim
