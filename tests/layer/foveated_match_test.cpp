// The layer against the fovea tool: hello_foveated with a scripted gaze, through the
// real loader, the layer and the simulated FOVE runtime; both eyes' captured
// frames equal `fovea render --mode foveated` for the same scene, eye pose, FOV
// and gaze pixel (fixed seeds, same method and k): bit for bit when the layer
// reconstructs on the CPU, within one 8-bit step on the GPU (lavapipe).
// With temporal history ("temporal": "image" or "rays") the captured (last)
// frame blends the frames since the eye's last TAA restart (the layer's
// temporal_reset_per_frame): the first traced frame, or a gaze jump beyond the TAA's
// reset distance. The first frame may come before the gaze replay's first
// sample and foveate the lens centre; at these small eyes the gaze is nearer
// than the reset distance, so that frame can stay in the history. `fovea
// render` renders the same frames: one per layer frame since the restart, each
// at the pixel the layer foveated it at (--gaze X,Y;X,Y;...), numbered as the
// layer numbers its frames (from 1: --first-frame is the restart's app frame
// + 1), since each frame's jitter is the seed plus its index.
#include <stb/stb_image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app_output.hpp"
#include "child_process.hpp"
#include "test_env.hpp"

namespace foveart::layer::test {
namespace {

using foveart::test::run_process;

constexpr int kTimeoutS = 900;
constexpr int kWidth = 320, kHeight = 360;  // small eyes: tables stay small under sanitizers
constexpr double kPi = 3.14159265358979323846;
// The scripted gaze, FOVE head space (+z forward): about 7 deg right, 4 deg down.
constexpr double kGaze[3] = {0.12, -0.07, 0.99};

// Both run the one foveated frame (foveation::FoveatedView) on the same view,
// gaze pixel, tables and seeds, and the same 8-bit sRGB encoding: the frames
// must be bit-identical. (A wrong pose, FOV, gaze pixel, seed, point set,
// weights, Y-flip or sRGB-vs-linear changes far more: a 1 px gaze shift gives
// 25.6 dB and ~47k differing pixels, a 1 mm eye shift 40-41 dB and ~8.6k.)

struct Diff {
  double psnr_db = 0.0;
  int max_abs = 0;
  std::size_t pixels_differing = 0;
};

Diff compare(const Rgb8& layer, const Rgb8& fovea) {
  Diff d;
  double sq = 0.0;
  const std::size_t pixels = layer.rgb.size() / 3;
  for (std::size_t p = 0; p < pixels; ++p) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int u = layer.rgb[p * 3 + c], v = fovea.rgb[p * 3 + c];
      sq += double(u - v) * (u - v);
      worst = std::max(worst, std::abs(u - v));
    }
    d.max_abs = std::max(d.max_abs, worst);
    d.pixels_differing += worst > 0;
  }
  const double mse = sq / double(layer.rgb.size());
  d.psnr_db = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  return d;
}

std::string join(const std::vector<double>& v) {
  std::ostringstream s;
  s.precision(17);
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? "," : "") << v[i];
  return s.str();
}

struct Method {
  const char* layer;  // hello_foveated --interpolation
  const char* fovea;  // fovea render --interpolation
  int k;              // the layer's neighbour count for it (NN: 4, as fovea render --k 4)
  const char* reconstruction;  // the layer config's: "cpu" is bit-exact, "gpu" within one 8-bit step
  const char* temporal = "off";  // hello_foveated and fovea render --temporal
  // Frames hello_foveated runs; with history, enough that the captured one
  // blends two or more even when the first came before the gaze.
  int frames = 2;
};

class LayerMatchesFoveaRender : public ::testing::TestWithParam<Method> {
 protected:
  void SetUp() override {
    ASSERT_TRUE(have_runtime()) << "the simulated runtime is part of every build: its manifest is missing";
    env_ = std::make_unique<IsolatedEnv>();
    configure_hello_foveated(*env_, GetParam().frames, GetParam().reconstruction);
    IsolatedEnv::set("FOVEART_SIM_HEAD", "static");
  }
  std::unique_ptr<IsolatedEnv> env_;
};

TEST_P(LayerMatchesFoveaRender, BothEyesMatchFoveaRender) {
  const Method m = GetParam();
  // A constant scripted gaze, 3 min at 120 Hz (longer than a cold table build
  // under sanitizers on a busy machine): every frame foveates the same pixel.
  const auto trace = env_->root() / "gaze.csv";
  {
    std::ofstream csv(trace);
    csv << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z\n";
    for (int i = 0; i < 21600; ++i) csv << i * 8333 << "," << i << ",1," << kGaze[0] << "," << kGaze[1] << "," << kGaze[2] << "\n";
  }
  const auto app = run_process({FOVEART_HELLO_FOVEATED, "--json", "--eye-size", std::to_string(kWidth),
                                std::to_string(kHeight), "--interpolation", m.layer, "--k", std::to_string(m.k),
                                "--density-scale", "1", "--rays-per-point", "1", "--temporal", m.temporal,
                                "--gaze-source", "provider", "--gaze-provider",
                                "replay:" + trace.string()},
                               env_->root() / "hello_foveated.log", kTimeoutS);
  ASSERT_EQ(app.exit_code, 0) << app.output;
  const auto stats = trailing_json(app.output);
  ASSERT_TRUE(stats.is_object()) << app.output;
  ASSERT_EQ(stats["frames_traced"], m.frames) << app.output;
  ASSERT_EQ(stats["views_fallback"], 0);
  ASSERT_EQ(stats["fallback_flags"], 0) << "the scripted gaze must be used, not fixed foveation";
  ASSERT_EQ(stats["reconstruction"], m.reconstruction) << app.output;
  ASSERT_EQ(stats["temporal"], m.temporal) << app.output;
  const bool on_gpu = std::string(m.reconstruction) == "gpu";
  const bool history = std::string(m.temporal) != "off";

  // The pixel the layer foveated each frame at, per eye, from its stats, and
  // where each eye's TAA history restarted. The first frame may come before the
  // replay's first sample (lens centre); the last one used the gaze
  // (fallback_flags above is the last frame's).
  const auto gaze_frames = stats["gaze_px_per_frame"];
  const auto resets = stats["temporal_reset_per_frame"];
  ASSERT_EQ(gaze_frames.size(), std::size_t(m.frames)) << app.output;
  ASSERT_EQ(resets.size(), std::size_t(m.frames)) << app.output;
  for (int i = 0; i < m.frames; ++i) ASSERT_EQ(gaze_frames[i][0], i) << "one traced frame per app frame";
  const char* eyes[2] = {"left", "right"};
  for (int e = 0; e < 2; ++e) {
    SCOPED_TRACE(eyes[e]);
    const auto& view = stats["views"][e];
    ASSERT_EQ(view["size_px"][0], kWidth);
    ASSERT_EQ(view["size_px"][1], kHeight);
    const auto fov_rad = view["fov_rad"].get<std::vector<double>>();
    std::vector<double> fov_deg;
    for (double a : fov_rad) fov_deg.push_back(a * 180.0 / kPi);
    std::vector<double> pose = view["position_m"].get<std::vector<double>>();
    for (double q : view["orientation_xyzw"].get<std::vector<double>>()) pose.push_back(q);
    const auto last = gaze_frames.back().get<std::vector<float>>();  // frame, x0, y0, x1, y1
    const glm::vec2 gaze_px(last[1 + 2 * e], last[2 + 2 * e]);
    ASSERT_NE(gaze_px, glm::round(glm::vec2(kWidth, kHeight) * 0.5f)) << "the gaze must be off the lens centre";
    // The frames the captured one is made of: the last since its history's
    // restart, each foveated where the layer's stats say (a first frame at the
    // lens centre stays in the history when the gaze is nearer than the TAA's
    // reset distance). fovea render cannot be told of a saccade or a blink.
    int restart = m.frames - 1;
    if (history) {
      while (restart > 0 && !resets[restart][e].get<bool>()) --restart;
      ASSERT_TRUE(resets[restart][e].get<bool>()) << "the first traced frame starts the history";
      ASSERT_LE(restart, m.frames - 2) << "the captured frame must blend two frames or more: " << app.output;
    }
    std::ostringstream gaze_arg;
    for (int i = restart; i < m.frames; ++i) {
      ASSERT_FALSE(stats["gaze_saccade_per_frame"][i].get<bool>()) << "frame " << i;
      ASSERT_FALSE(stats["gaze_blink_per_frame"][i].get<bool>()) << "frame " << i;
      const auto frame = gaze_frames[i].get<std::vector<float>>();
      gaze_arg << (i > restart ? ";" : "") << frame[1 + 2 * e] << "," << frame[2 + 2 * e];
    }

    const auto prefix = env_->root() / (std::string("fovea_") + eyes[e]);
    const auto render = run_process(
        {FOVEART_FOVEA, "render", "--scene", "default", "--mode", "foveated", "--interpolation", m.fovea, "--k",
         std::to_string(m.k), "--rays-per-point", "1", "--density-scale", "1", "--seed", "1", "--size",
         std::to_string(kWidth) + "x" + std::to_string(kHeight), "--fov-deg", join(fov_deg), "--pose", join(pose),
         "--gaze", gaze_arg.str(), "--temporal", m.temporal, "--frames", std::to_string(m.frames - restart),
         "--first-frame", std::to_string(restart + 1), "--cache-dir", FOVEART_TEST_CACHE_DIR, "--threads", "2", "--out",
         prefix.string(), "--json"},
        env_->root() / (std::string("fovea_") + eyes[e] + ".log"), kTimeoutS);
    ASSERT_EQ(render.exit_code, 0) << render.output;

    const fs::path layer_frame = captured_frame(env_->root() / "frames", m.frames - 1, eyes[e]);
    const Rgb8 layer_img = load_rgb(layer_frame);
    const Rgb8 fovea_img = load_rgb(prefix.string() + "_foveated.png");
    ASSERT_EQ(layer_img.width, kWidth) << layer_frame;
    ASSERT_EQ(layer_img.height, kHeight);
    ASSERT_EQ(fovea_img.width, kWidth);
    ASSERT_EQ(fovea_img.height, kHeight);
    const Diff d = compare(layer_img, fovea_img);
    RecordProperty(std::string(eyes[e]) + "_psnr_db", std::to_string(d.psnr_db));
    std::printf("%s eye, %s on the %s, temporal %s, frames since the restart at gaze %s px: PSNR %.2f dB, "
                "max |diff| %d, %zu of %d pixels differ\n",
                eyes[e], m.fovea, m.reconstruction, m.temporal, gaze_arg.str().c_str(), d.psnr_db, d.max_abs,
                d.pixels_differing, kWidth * kHeight);
    if (on_gpu) {
      EXPECT_LE(d.max_abs, 1);  // the GPU's own float order and pow: one 8-bit step at most
    } else {
      EXPECT_EQ(d.pixels_differing, 0u);
      EXPECT_EQ(d.max_abs, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, LayerMatchesFoveaRender,
                         ::testing::Values(Method{"msm", "msm", 5, "cpu"}, Method{"nearest", "nearest", 4, "cpu"},
                                           Method{"msm", "msm", 5, "gpu"}, Method{"nearest", "nearest", 4, "gpu"},
                                           Method{"msm", "msm", 5, "cpu", "image", 3},
                                           Method{"msm", "msm", 5, "cpu", "rays", 3},
                                           Method{"msm", "msm", 5, "gpu", "image", 3},
                                           Method{"msm", "msm", 5, "gpu", "rays", 3}),
                         [](const ::testing::TestParamInfo<Method>& p) {
                           const std::string temporal = p.param.temporal;
                           return std::string(p.param.fovea) + "_" + p.param.reconstruction +
                                  (temporal == "off" ? "" : "_" + temporal);
                         });

}  // namespace
}  // namespace foveart::layer::test
