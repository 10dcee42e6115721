// hello_foveated through the real loader, the layer and the simulated FOVE
// runtime: both eyes traced every frame, gaze lost mid-run, failing engines.
#include <stb/stb_image.h>

#include <cmath>
#include <fstream>
#include <set>
#include <utility>
#include <string>

#include <iostream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app_output.hpp"
#include "child_process.hpp"
#include "foveation/device.hpp"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

using foveart::test::ProcessResult;
using foveart::test::run_process;

constexpr int kTimeoutS = 900;

struct AppRun {
  ProcessResult process;
  nlohmann::json stats;
};

// Mean and spread of an 8-bit image's channels.
struct ImageSummary {
  bool loaded = false;
  int width = 0, height = 0;
  double mean = 0.0;
  double min = 255.0, max = 0.0;
};

ImageSummary summarize(const fs::path& png) {
  ImageSummary s;
  int channels = 0;
  unsigned char* data = stbi_load(png.c_str(), &s.width, &s.height, &channels, 3);
  if (data == nullptr) return s;
  s.loaded = true;
  const std::size_t n = std::size_t(s.width) * std::size_t(s.height) * 3;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sum += data[i];
    s.min = std::min<double>(s.min, data[i]);
    s.max = std::max<double>(s.max, data[i]);
  }
  s.mean = sum / static_cast<double>(n);
  stbi_image_free(data);
  return s;
}

class HelloFoveated : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(have_runtime()) << "the simulated runtime is part of every build: its manifest is missing";
    env_ = std::make_unique<IsolatedEnv>();
    configure_hello_foveated(*env_, 3);  // one table cache shared by the suite
    for (const char* name : {"FOVEART_SIM_CAPTURE_EVERY", "FOVEART_SIM_EYE_TRACKING", "FOVEART_SIM_GAZE"}) {
      ::unsetenv(name);
    }
  }

  AppRun launch(std::vector<std::string> args) {
    // A quarter-size eye image keeps the tables small enough for sanitizer builds;
    // the layer follows the app's imageRect.
    args.insert(args.begin(), {FOVEART_HELLO_FOVEATED, "--json", "--eye-size", "320", "360"});
    AppRun r;
    r.process = run_process(args, env_->root() / "hello_foveated.log", kTimeoutS);
    r.stats = trailing_json(r.process.output);
    return r;
  }

  fs::path frame(int index, const char* eye) const { return captured_frame(env_->root() / "frames", index, eye); }

  std::unique_ptr<IsolatedEnv> env_;
};

TEST_F(HelloFoveated, TracesBothEyesEveryFrame) {
  const auto r = launch({"--gaze-source", "none"});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["frames_submitted"], 3);
  EXPECT_EQ(r.stats["frames_traced"], 3);
  EXPECT_EQ(r.stats["views_fallback"], 0);
  EXPECT_EQ(r.stats["callback_failures"], 0);
  for (int e = 0; e < 2; ++e) {
    EXPECT_GT(r.stats["eyes"][e]["points"].get<int>(), 10000) << "eye " << e;
    EXPECT_EQ(r.stats["eyes"][e]["rays"], r.stats["eyes"][e]["points"]);
  }
  // No gaze requested: fixed foveation, flagged.
  EXPECT_EQ(r.stats["fallback_flags"].get<uint64_t>() & 1u, 1u);
  for (const char* eye : {"left", "right"}) {
    const auto img = summarize(frame(2, eye));
    ASSERT_TRUE(img.loaded) << frame(2, eye);
    EXPECT_EQ(img.width, 320);
    EXPECT_EQ(img.height, 360);
    // The app only cleared its images to grey (sRGB 124): a traced scene has contrast.
    EXPECT_GT(img.max - img.min, 150.0) << eye;
  }
}

// XrFoveatedRendererDensityStatsFOVEART through hello_foveated --json on the CPU trace:
// with content density on, the last frame thinned points and each host stage took time
// (levels may round to nothing: the sum is checked), the device's stages stay 0; off, all 0.
void expect_cpu_density_stats(const nlohmann::json& stats, int e, bool density_on) {
  const nlohmann::json& eye = stats["density"]["eyes"][e];
  ASSERT_TRUE(eye.is_object()) << stats.dump();
  std::cout << "[ measured ] eye " << e << " density stats " << eye.dump() << "\n";
  EXPECT_EQ(eye["gpu_fill_ms"].get<double>(), 0.0) << "eye " << e;
  EXPECT_EQ(eye["gpu_contrast_ms"].get<double>(), 0.0) << "eye " << e;
  const double host_ms = eye["levels_ms"].get<double>() + eye["test_ms"].get<double>() +
                         eye["observe_ms"].get<double>() + eye["fill_ms"].get<double>();
  if (!density_on) {
    EXPECT_EQ(eye["points_thinned"].get<uint64_t>(), 0u) << "eye " << e;
    EXPECT_EQ(host_ms, 0.0) << "eye " << e;
    return;
  }
  EXPECT_GT(eye["points_thinned"].get<uint64_t>(), 0u) << "eye " << e;
  for (const char* stage : {"test_ms", "observe_ms", "fill_ms"})
    EXPECT_GT(eye[stage].get<double>(), 0.0) << "eye " << e << " " << stage;
  EXPECT_GT(stats["density"]["per_frame"]["host_ms"][e]["p50"].get<double>(), 0.0) << "eye " << e;
}

// Content-aware density through the layer's config, with either history (the image
// history, and the render cache, which takes only the traced points' rays): from the
// second frame on, the flat tiles trace fewer points; the frames stay the scene's.
TEST_F(HelloFoveated, ContentContrastTracesFewerRaysWhereTheViewIsFlat) {
  // Density scale 4 puts the pixel-exact fovea's edge inside these small eyes.
  configure_hello_foveated(*env_, 3, "auto", {}, R"("density_scale": 4)");
  const auto full = launch({"--gaze-source", "none"});
  ASSERT_EQ(full.process.exit_code, 0) << full.process.output;
  const auto full_frame = summarize(frame(2, "left"));
  for (const char* temporal : {"image", "rays"}) {
    configure_hello_foveated(*env_, 3, "auto", temporal, R"("density_scale": 4, "content_contrast": 0.9)");
    const auto thinned = launch({"--gaze-source", "none"});
    ASSERT_EQ(thinned.process.exit_code, 0) << thinned.process.output;
    EXPECT_EQ(thinned.stats["views_fallback"], 0) << temporal;
    for (int e = 0; e < 2; ++e) {
      const double rays = thinned.stats["eyes"][e]["rays"].get<double>();
      const double full_rays = full.stats["eyes"][e]["rays"].get<double>();
      std::cout << "[ measured ] " << temporal << ", eye " << e << ": " << rays << " rays of " << full_rays
                << " without\n";
      EXPECT_LT(rays, 0.9 * full_rays) << temporal << ", eye " << e;
      EXPECT_GT(rays, 0.2 * full_rays) << temporal << ", eye " << e << ": level 0 and the fovea stay";
      ASSERT_NO_FATAL_FAILURE(expect_cpu_density_stats(thinned.stats, e, true)) << temporal;
      ASSERT_NO_FATAL_FAILURE(expect_cpu_density_stats(full.stats, e, false));
    }
    const auto img = summarize(frame(2, "left"));
    ASSERT_TRUE(img.loaded) << temporal;
    std::cout << "[ measured ] " << temporal << ", left eye frame 2 mean " << img.mean << " (without: "
              << full_frame.mean << ")\n";
    EXPECT_NEAR(img.mean, full_frame.mean, 2.0) << temporal << ": the same scene";
    EXPECT_GT(img.max - img.min, 150.0) << temporal;
  }
}

// Rays per point by contrast double with eccentricity by default where the history is the render
// cache (content_rays_doubling_for), through the app and the layer: with "rays" an eye casts fewer
// rays than with the config's "content_rays_doubling_deg": 0; with the image history the default
// is off, so naming 0 casts the same rays.
TEST_F(HelloFoveated, RaysDoublingWithEccentricityFollowsTheHistoryByDefault) {
  for (const char* temporal : {"rays", "image"}) {
    const std::vector<std::string> args{"--gaze-source", "none", "--rays-per-point", "4", "--temporal", temporal};
    configure_hello_foveated(*env_, 3, "auto", {}, R"("density_scale": 4)");
    const auto by_default = launch(args);
    ASSERT_EQ(by_default.process.exit_code, 0) << by_default.process.output;
    configure_hello_foveated(*env_, 3, "auto", {}, R"("density_scale": 4, "content_rays_doubling_deg": 0)");
    const auto off = launch(args);
    ASSERT_EQ(off.process.exit_code, 0) << off.process.output;
    for (int e = 0; e < 2; ++e) {
      const uint64_t rays = by_default.stats["eyes"][e]["rays"].get<uint64_t>();
      const uint64_t rays_off = off.stats["eyes"][e]["rays"].get<uint64_t>();
      std::cout << "[ measured ] " << temporal << ", eye " << e << ": " << rays << " rays by default, " << rays_off
                << " with the doubling off\n";
      if (std::string(temporal) == "rays") {
        EXPECT_LT(rays, rays_off) << "eye " << e << ": the outer points cast fewer";
      } else {
        EXPECT_EQ(rays, rays_off) << "eye " << e;
      }
    }
  }
}

TEST_F(HelloFoveated, GazeLostMidRunFallsBackToFixedFoveation) {
  // 3 samples (17 ms) of valid gaze at 120 Hz, then the tracker loses the eye for good. The
  // provider steps with the frames' display time, so the replay keeps step with the 70 Hz frames
  // however fast the machine runs them: the hold (200 ms) ends before frame 16 of 20.
  const auto trace = env_->root() / "gaze.csv";
  {
    std::ofstream csv(trace);
    csv << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
    for (int i = 0; i < 2400; ++i) {
      const bool valid = i < 3;
      csv << i * 8333 << "," << i << "," << (valid ? 1 : 0) << ","
          << (valid ? "0.1,0.05,0.9937" : "nan,nan,nan") << "\n";
    }
  }
  configure_hello_foveated(*env_, 20, "auto", {}, R"("gaze_clock": "display_time")");
  const auto r = launch({"--gaze-source", "provider", "--gaze-provider", "replay:" + trace.string()});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["frames_traced"], 20);
  EXPECT_EQ(r.stats["views_fallback"], 0);
  EXPECT_GT(r.stats["gaze_lost_frames"].get<int>(), 0);
}

// The frame path itself (layer swapchains, upload or GPU reconstruction, sync)
// under both validation layers, Vulkan's with synchronization validation, on
// the CPU and the GPU path. Core validation must sit below FoveaRT: above it,
// it would reject the extension's opt-in struct it does not know.
class HelloFoveatedValidated : public HelloFoveated, public ::testing::WithParamInterface<const char*> {};

TEST_P(HelloFoveatedValidated, FramePathUnderValidationLayersHasNoErrors) {
  configure_hello_foveated(*env_, 3, GetParam());
  IsolatedEnv::set("XR_API_LAYER_PATH", (explicit_layer_dir().string() + ":" + kSystemExplicitLayers).c_str());
  IsolatedEnv::set("XR_ENABLE_API_LAYERS", "XR_APILAYER_FOVEART_foveated_ray_tracing:XR_APILAYER_LUNARG_core_validation");
  IsolatedEnv::set("VK_INSTANCE_LAYERS", "VK_LAYER_KHRONOS_validation");
  IsolatedEnv::set("VK_LAYER_PATH", "/usr/share/vulkan/explicit_layer.d");
  IsolatedEnv::set("VK_LAYER_ENABLES", "VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT");
  IsolatedEnv::set("XR_LOADER_DEBUG", "info");
  IsolatedEnv::set("VK_LOADER_DEBUG", "layer");
  const auto r = launch({"--gaze-source", "none", "--no-explicit-layer"});
  for (const char* name : {"XR_ENABLE_API_LAYERS", "VK_INSTANCE_LAYERS", "VK_LAYER_PATH", "VK_LAYER_ENABLES",
                           "XR_LOADER_DEBUG", "VK_LOADER_DEBUG"}) {
    ::unsetenv(name);
  }
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["reconstruction"], GetParam());
  for (const char* loaded : {"succeeded loading layer XR_APILAYER_LUNARG_core_validation",
                             "Insert instance layer \"VK_LAYER_KHRONOS_validation\""}) {
    EXPECT_NE(r.process.output.find(loaded), std::string::npos) << "missing: " << loaded;
  }
  for (const char* marker : {"Validation Error", "VUID-", "VALID_ERROR"}) {
    EXPECT_EQ(r.process.output.find(marker), std::string::npos) << marker << " in:\n" << r.process.output;
  }
  EXPECT_EQ(r.stats["frames_traced"], 3);
}

INSTANTIATE_TEST_SUITE_P(Paths, HelloFoveatedValidated, ::testing::Values("cpu", "gpu"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

// XR_EXT_eye_gaze_interaction as the gaze source. The simulated runtime plays
// a trace of three fixations and a blink, 50 ms each; frames.csv has its gaze
// sample at each frame's display time in the trace's head space (+z forward; head
// static, so the gaze pixel follows from the symmetric FOV).
struct CsvGaze {
  bool valid = false;
  double x = 0, y = 0, z = 1;
};

std::vector<CsvGaze> read_frames_csv(const fs::path& path) {
  std::vector<CsvGaze> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header; the gaze is the last four columns
  while (std::getline(in, line)) {
    std::vector<std::string> cols;
    std::size_t start = 0;
    for (std::size_t comma; (comma = line.find(',', start)) != std::string::npos; start = comma + 1) {
      cols.push_back(line.substr(start, comma - start));
    }
    cols.push_back(line.substr(start));
    if (cols.size() < 4) continue;
    const std::size_t n = cols.size();
    rows.push_back({cols[n - 4] == "1", std::stod(cols[n - 3]), std::stod(cols[n - 2]), std::stod(cols[n - 1])});
  }
  return rows;
}

// Pixel of a head-space direction in a 320x360 eye of the simulated FOVE 0
// (foveation/device.hpp: symmetric, square pixels).
std::pair<double, double> expected_pixel(const CsvGaze& g) {
  const double tan_h = std::tan(foveation::fove0().eye_fov_rad.right);
  const double tan_v = std::tan(foveation::fove0().eye_fov_rad.up);
  return {std::round(160.0 * (g.x / g.z / tan_h + 1.0)), std::round(180.0 * (1.0 - g.y / g.z / tan_v))};
}

TEST_F(HelloFoveated, EyeGazeInteractionFollowsTheRuntimesScriptedGaze) {
  const auto trace = env_->root() / "gaze.csv";
  {
    std::ofstream csv(trace);
    csv << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
    const char* segments[] = {"1,0.1,-0.05,0.9937", "1,0.2,0.1,0.9747", "0,0,0,1", "1,-0.25,-0.08,0.9649"};
    for (int i = 0; i < 24; ++i) csv << i * 8333 << "," << i << "," << segments[i / 6] << "\n";
  }
  IsolatedEnv::set("FOVEART_SIM_GAZE", trace);
  IsolatedEnv::set("FOVEART_SIM_FRAMES", "14");
  IsolatedEnv::set("FOVEART_SIM_CAPTURE_EVERY", "1000");
  const auto r = launch({"--gaze-source", "eye_gaze_interaction", "--temporal", "off"});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  // The app did not enable the extension: the layer did, and says so.
  EXPECT_NE(r.process.output.find("hidden from the app"), std::string::npos) << r.process.output;
  const auto csv = read_frames_csv(env_->root() / "frames" / "frames.csv");
  ASSERT_EQ(csv.size(), 14u);
  const auto& per_frame = r.stats["gaze_px_per_frame"];
  ASSERT_EQ(per_frame.size(), 14u);
  int blinks = 0;
  for (const auto& row : csv) blinks += row.valid ? 0 : 1;
  EXPECT_GT(blinks, 0);
  EXPECT_EQ(r.stats["gaze_lost_frames"], blinks);  // blink: fixed foveation, counted
  std::set<std::pair<double, double>> fixations;
  for (const auto& row : per_frame) {
    const auto f = static_cast<std::size_t>(row[0].get<double>());
    ASSERT_LT(f, csv.size());
    const auto expected = csv[f].valid ? expected_pixel(csv[f]) : std::pair{160.0, 180.0};
    fixations.insert(expected);
    for (int e = 0; e < 2; ++e) {
      EXPECT_NEAR(row[1 + 2 * e].get<double>(), expected.first, 1.0) << "frame " << f << " eye " << e;
      EXPECT_NEAR(row[2 + 2 * e].get<double>(), expected.second, 1.0) << "frame " << f << " eye " << e;
    }
  }
  EXPECT_EQ(fixations.size(), 4u) << "three fixations and the lens centre during the blink";
}

TEST_F(HelloFoveated, AppUsingItsOwnGazeActionKeepsItAndTheLayerStillGetsGaze) {
  IsolatedEnv::set("FOVEART_SIM_FRAMES", "4");
  const auto r = launch({"--gaze-source", "eye_gaze_interaction", "--app-actions"});
  // Every action call of the app succeeded (hello_foveated exits 1 otherwise).
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["app_gaze_located_frames"], 4);
  EXPECT_EQ(r.stats["frames_traced"], 4);
  EXPECT_EQ(r.stats["gaze_source"], "eye_gaze_interaction");
  EXPECT_EQ(r.stats["gaze_lost_frames"], 0);
  // Rode along the app's attach and sync: nothing attached on its own, nothing hidden.
  EXPECT_EQ(r.process.output.find("attached its own"), std::string::npos) << r.process.output;
  EXPECT_EQ(r.process.output.find("hidden from the app"), std::string::npos) << r.process.output;
}

TEST_F(HelloFoveated, RuntimeWithoutEyeTrackingGivesFixedFoveation) {
  IsolatedEnv::set("FOVEART_SIM_EYE_TRACKING", "0");
  const auto r = launch({"--gaze-source", "eye_gaze_interaction"});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_NE(r.process.output.find("supportsEyeGazeInteraction = XR_FALSE"), std::string::npos) << r.process.output;
  EXPECT_EQ(r.stats["frames_traced"], 3);
  EXPECT_EQ(r.stats["gaze_lost_frames"], 3);
  EXPECT_EQ(r.stats["fallback_flags"].get<uint64_t>() & 1u, 1u);
  for (const auto& row : r.stats["gaze_px_per_frame"]) {
    EXPECT_EQ(row[1].get<double>(), 160.0);
    EXPECT_EQ(row[2].get<double>(), 180.0);
  }
}

class FailingEngine : public HelloFoveated, public ::testing::WithParamInterface<const char*> {};

TEST_P(FailingEngine, ViewsFallBackToTheAppsImage) {
  const auto r = launch({"--gaze-source", "none", "--fault", GetParam()});
  ASSERT_EQ(r.process.exit_code, 0) << r.process.output;
  ASSERT_TRUE(r.stats.is_object()) << r.process.output;
  EXPECT_EQ(r.stats["frames_traced"], 0);
  EXPECT_EQ(r.stats["views_fallback"], 6);
  const std::string fault = GetParam();
  if (fault == "nan") {
    EXPECT_GT(r.stats["invalid_colours"].get<int>(), 0);
  } else {
    EXPECT_GT(r.stats["callback_failures"].get<int>(), 0);
  }
  // Logged once, not per frame.
  std::size_t lines = 0;
  for (std::size_t at = r.process.output.find("logged once"); at != std::string::npos;
       at = r.process.output.find("logged once", at + 1)) {
    ++lines;
  }
  EXPECT_EQ(lines, 1u);
  // What the runtime showed is the app's own grey placeholder, not garbage.
  const auto img = summarize(frame(2, "left"));
  ASSERT_TRUE(img.loaded);
  EXPECT_NEAR(img.min, 124.0, 1.0);
  EXPECT_NEAR(img.max, 124.0, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Faults, FailingEngine, ::testing::Values("nan", "error", "throw"),
                         [](const ::testing::TestParamInfo<const char*>& p) { return std::string(p.param); });

}  // namespace
}  // namespace foveart::layer::test
