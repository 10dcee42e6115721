// `fovea-eval perceptual` in process: bad arguments exit 2 naming the problem; an identical pair
// reads 0, a visible patch at the gaze is detected, the heat map has the images' size, the
// threshold multiple is reported when asked for, over 1 for a seen difference and under for an unseen,
// and lower for a flickering difference.
#include <eval/cmd_perceptual.hpp>
#include <eval/pfm.hpp>

#include <toolkit/image_io.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "gltf_fixtures.hpp"  // engine_test::TempDir

namespace fs = std::filesystem;
using namespace foveart;

namespace {

// Grey 64x48 with, when c > 0, a 4 cpd (at 20 ppd) patch of contrast c at (32, 24).
foveation::ImageRgb image(double c) {
  foveation::ImageRgb img(64, 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const double r2 = double((x - 32) * (x - 32) + (y - 24) * (y - 24));
      const float v = float(0.5 * (1.0 + c * std::exp(-r2 / 72.0) * std::cos(2.0 * M_PI * 0.2 * x)));
      for (int k = 0; k < 3; ++k) img.at(x, y)[k] = v;
    }
  return img;
}

int run(const eval::PerceptualCommand& c, std::string* out, std::string* err) {
  std::ostringstream o, e;
  const int code = eval::run_perceptual(c, o, e);
  *out = o.str(), *err = e.str();
  return code;
}

}  // namespace

TEST(PerceptualCommand, BadArgumentsExitTwoNamingTheProblem) {
  engine_test::TempDir dir;
  std::string error, out, err;
  const std::string a = (dir.path / "a.pfm").string(), small = (dir.path / "small.pfm").string();
  ASSERT_TRUE(eval::write_pfm(a, image(0.0), &error)) << error;
  ASSERT_TRUE(eval::write_pfm(small, foveation::ImageRgb(16, 16), &error)) << error;
  eval::PerceptualCommand c;
  c.test = a, c.reference = small, c.gaze_px = glm::vec2(8, 8);
  EXPECT_EQ(run(c, &out, &err), 2);
  EXPECT_NE(err.find("must be the same size"), std::string::npos) << err;
  c.reference = a;
  c.gaze_px.reset();
  EXPECT_EQ(run(c, &out, &err), 2);
  EXPECT_NE(err.find("--gaze"), std::string::npos) << err;
  c.gaze_px = glm::vec2(100, 8);
  EXPECT_EQ(run(c, &out, &err), 2);
  EXPECT_NE(err.find("off the 64x48 image"), std::string::npos) << err;
  c.gaze_px = glm::vec2(32, 24), c.fov_deg = 90.0, c.ppd = 20.0;
  EXPECT_EQ(run(c, &out, &err), 2);
  EXPECT_NE(err.find("not both"), std::string::npos) << err;
  c.fov_deg.reset(), c.flicker_hz = -5.0;
  EXPECT_EQ(run(c, &out, &err), 2);
  EXPECT_NE(err.find("--flicker-hz"), std::string::npos) << err;
}

TEST(PerceptualCommand, IdenticalPairReadsZeroAndAPatchAtTheGazeIsDetected) {
  engine_test::TempDir dir;
  std::string error, out, err;
  const std::string ref = (dir.path / "ref.pfm").string(), test = (dir.path / "test.pfm").string();
  ASSERT_TRUE(eval::write_pfm(ref, image(0.0), &error)) << error;
  ASSERT_TRUE(eval::write_pfm(test, image(0.5), &error)) << error;
  eval::PerceptualCommand c;
  c.test = ref, c.reference = ref, c.gaze_px = glm::vec2(32, 24), c.ppd = 20.0, c.json = true;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["p_detect_max"].get<double>(), 0.0);
  c.test = test;
  c.heatmap_png = (dir.path / "heat.png").string();
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  j = nlohmann::json::parse(out);
  EXPECT_GT(j["rings"][0]["p_detect_max"].get<double>(), 0.5) << out;  // contrast 0.5 at 4 cpd: far above threshold
  EXPECT_EQ(j["pixels_per_deg"].get<double>(), 20.0);
  foveation::ImageRgb heat;
  ASSERT_TRUE(toolkit::read_image(c.heatmap_png, toolkit::PngValues::display, &heat, &error)) << error;
  EXPECT_EQ(heat.width_px, 64);
  EXPECT_EQ(heat.height_px, 48);
  EXPECT_GT(heat.at(32, 24)[0], 0.5f);  // P > 0.5 at the patch's centre
}

TEST(PerceptualCommand, ThresholdMultipleOnlyWhenAskedForAndAboveOneWhereSeen) {
  engine_test::TempDir dir;
  std::string error, out, err;
  const std::string ref = (dir.path / "ref.pfm").string(), seen = (dir.path / "seen.pfm").string(),
                    faint = (dir.path / "faint.pfm").string();
  ASSERT_TRUE(eval::write_pfm(ref, image(0.0), &error)) << error;
  ASSERT_TRUE(eval::write_pfm(seen, image(0.5), &error)) << error;
  ASSERT_TRUE(eval::write_pfm(faint, image(0.0005), &error)) << error;
  eval::PerceptualCommand c;
  c.test = seen, c.reference = ref, c.gaze_px = glm::vec2(32, 24), c.ppd = 20.0, c.json = true;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  EXPECT_TRUE(nlohmann::json::parse(out)["threshold_multiple"].is_null()) << out;
  c.threshold_multiple = true;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  auto j = nlohmann::json::parse(out);
  EXPECT_GT(j["threshold_multiple"].get<double>(), 1.0) << out;
  EXPECT_GE(j["p_detect_max"].get<double>(), 0.5) << out;
  for (const auto& ring : j["rings"]) EXPECT_TRUE(ring["threshold_multiple"].is_null()) << "not asked for: " << out;
  // Per ring: the image's multiple is its most visible ring's; a ring without pixels has none.
  c.ring_multiples = true;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  j = nlohmann::json::parse(out);
  double largest = 0.0;
  for (const auto& ring : j["rings"]) {
    ASSERT_EQ(ring["threshold_multiple"].is_null(), ring["pixels"].get<int>() == 0) << out;
    if (!ring["threshold_multiple"].is_null()) largest = std::max(largest, ring["threshold_multiple"].get<double>());
  }
  EXPECT_DOUBLE_EQ(largest, j["threshold_multiple"].get<double>()) << out;
  c.json = false;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  EXPECT_NE(out.find("threshold multiple\n"), std::string::npos) << "the table's column: " << out;
  c.json = true, c.ring_multiples = false;
  c.test = faint;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  j = nlohmann::json::parse(out);
  EXPECT_GT(j["threshold_multiple"].get<double>(), 0.0) << out;
  EXPECT_LT(j["threshold_multiple"].get<double>(), 1.0) << out;
  EXPECT_LT(j["p_detect_max"].get<double>(), 0.5) << out;
  c.json = false;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  EXPECT_NE(out.find("threshold multiple 0."), std::string::npos) << out;
  // The seen patch flickering at 35 Hz: less far above threshold than held still.
  c.test = seen, c.json = true;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  const double still = nlohmann::json::parse(out)["threshold_multiple"].get<double>();
  c.flicker_hz = 35.0;
  ASSERT_EQ(run(c, &out, &err), 0) << err;
  j = nlohmann::json::parse(out);
  EXPECT_EQ(j["flicker_hz"].get<double>(), 35.0);
  EXPECT_LT(j["threshold_multiple"].get<double>(), still) << out;
}
