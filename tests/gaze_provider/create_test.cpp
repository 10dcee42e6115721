// create_gaze_provider(): source strings and their errors.
#include <gtest/gtest.h>

#include "gaze_provider/backends.h"

using namespace foveart::gaze;

TEST(CreateProvider, KnownSources) {
  CreateResult sim = create_gaze_provider("sim");
  ASSERT_TRUE(sim) << sim.error;
  EXPECT_EQ(sim.provider->source(), GazeSourceKind::simulated);
  EXPECT_DOUBLE_EQ(sim.provider->nominal_rate_hz(), 120.0);
  EXPECT_FALSE(sim.provider->latest().has_value()) << "nothing before start()";
  EXPECT_TRUE(create_gaze_provider("sim:123"));
}

TEST(CreateProvider, BadSourcesSayWhy) {
  struct Case {
    const char* source;
    const char* expect;
  } cases[] = {{"", "unknown gaze source"},
               {"tobii", "unknown gaze source"},
               {"sim:abc", "seed"},
               {"replay", "replay:FILE"},
               {"replay:/nonexistent.csv", "cannot open"},
               {"hid:12345:1", "hid:VID:PID"},
               {"hid:2a5e", "hid:VID:PID"}};
  for (const Case& c : cases) {
    CreateResult r = create_gaze_provider(c.source);
    EXPECT_FALSE(r) << c.source;
    EXPECT_NE(r.error.find(c.expect), std::string::npos) << c.source << " -> " << r.error;
  }
  ProviderOptions options;
  options.sim.rate_hz = -1.0;
  EXPECT_FALSE(create_gaze_provider("sim", options));
}
