// `fovea-eval motion`: bad motion files and options are errors naming what
// is wrong with a non-zero exit; a tiny sequence reports per-ring flicker and
// error against the reference sequence for every temporal variant at equal rays, and
// says when the reference's own noise lies too close to a track's.
#include "gltf_fixtures.hpp"

#include <eval/cmd_motion.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using foveart::eval::MotionOptions;
using foveart::eval::run_motion;
namespace fs = std::filesystem;

namespace {

MotionOptions tiny_motion() {
  MotionOptions o;
  o.render.mode = "both";
  o.motion = "builtin";
  o.render.size_px = glm::ivec2(64, 72);  // 1.5 deg per pixel: every ring has pixels
  o.render.frames = 3;
  o.start_s = 0.5;  // a fixation: no saccade, no blink
  o.render.threads = 2;
  o.render.json = true;
  return o;
}

// tiny_motion() measured against an 8-ray reference sequence cached in `dir`.
MotionOptions tiny_motion_with_reference(const fs::path& dir, const std::string& variants) {
  MotionOptions o = tiny_motion();
  o.temporal = variants;
  o.reference.spp = "8";
  o.render.cache_dir = (dir / "cache").string();
  return o;
}

// run_motion's JSON report; null, and a failure with its message, when it fails.
nlohmann::json run_json(const MotionOptions& o) {
  std::ostringstream out, err;
  const int code = run_motion(o, out, err);
  EXPECT_EQ(code, 0) << err.str();
  return code == 0 ? nlohmann::json::parse(out.str()) : nlohmann::json();
}

// The fovea-eval binary beside this test with `args`: its exit status (-1 if it
// did not exit) and what it wrote to stderr.
int run_fovea_binary(const std::string& args, const fs::path& dir, std::string* err_text) {
  const fs::path fovea = fs::read_symlink("/proc/self/exe").parent_path() / "fovea-eval";
  if (!fs::exists(fovea)) {
    *err_text = fovea.string() + " is missing";
    return -1;
  }
  const std::string cmd = "'" + fovea.string() + "' " + args + " 2>'" + (dir / "err").string() + "' >/dev/null";
  const int status = std::system(cmd.c_str());
  std::ifstream in(dir / "err");
  std::ostringstream text;
  text << in.rdbuf();
  *err_text = text.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int run(const MotionOptions& o, std::string* err_text) {
  std::ostringstream out, err;
  const int code = run_motion(o, out, err);
  *err_text = err.str();
  return code;
}

}  // namespace

TEST(RenderMotion, BadMotionFileIsAnErrorNamingTheFileAndLine) {
  engine_test::TempDir dir;
  const fs::path file = dir.path / "motion.csv";
  std::ofstream(file) << "time_s,qx,qy,qz,qw,px,py,pz,gx,gy,gz,valid\n0,0,0,0,1,0,1.6,0,0,0,-1,1\n"
                         "0.5,0,0,0,1,0,1.6,0,0,0,-1\n";  // 11 columns
  MotionOptions o = tiny_motion();
  o.motion = file.string();
  std::string err;
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("motion.csv:3: 11 columns"), std::string::npos) << err;
  o.motion = (dir.path / "absent.csv").string();
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("absent.csv: no such file"), std::string::npos) << err;

  // The binary: the same message and a non-zero exit status.
  EXPECT_EQ(run_fovea_binary("motion --size 64x72 --motion '" + file.string() + "'", dir.path, &err), 2) << err;
  EXPECT_NE(err.find("11 columns"), std::string::npos) << err;
}

// The lab takes --temporal as the product does, with its own variants too; the old --taa and
// --taa-mean-while-young are errors naming the new options.
TEST(RenderMotion, OldTaaOptionsNameTemporal) {
  engine_test::TempDir dir;
  std::string err;
  EXPECT_NE(run_fovea_binary("motion --size 64x72 --taa off,reproject", dir.path, &err), 0) << err;
  EXPECT_NE(err.find("--taa: no longer an option here: give --temporal"), std::string::npos) << err;
  EXPECT_NE(run_fovea_binary("motion --size 64x72 --taa-mean-while-young", dir.path, &err), 0) << err;
  EXPECT_NE(err.find("--temporal-mean-while-young"), std::string::npos) << err;
  EXPECT_NE(run_fovea_binary("motion --size 64x72 --temporal off,reproject", dir.path, &err), 0) << err;
  EXPECT_NE(err.find("'reproject' is not off, restart, image, rays or rays-kept"), std::string::npos) << err;
}

TEST(RenderMotion, FramesTemporalAndWindowAreValidated) {
  std::string err;
  MotionOptions o = tiny_motion();
  o.render.frames = 1;
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--frames must be at least 2"), std::string::npos) << err;
  o = tiny_motion();
  o.render.frames = 300;  // 300 frames at 70 fps from 0.5 s end after the 4 s motion
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("past the motion's end"), std::string::npos) << err;
  o = tiny_motion();
  o.render.frames = 0;
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--frames"), std::string::npos) << err;
  o = tiny_motion();
  o.temporal = "off,sometimes";
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("'sometimes' is not off, restart, image, rays or rays-kept"), std::string::npos) << err;
  o.temporal = "off,off";
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("given twice"), std::string::npos) << err;
  o.temporal = "image,";
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--temporal"), std::string::npos) << err;
  o = tiny_motion();
  o.render.mode = "full";
  o.temporal = "image";
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--temporal needs --mode foveated or both"), std::string::npos) << err;
  o = tiny_motion();
  o.motion.clear();
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--motion is required"), std::string::npos) << err;
  o = tiny_motion();
  o.fps = 0.0;
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--fps"), std::string::npos) << err;
  o = tiny_motion();
  o.start_s = 4.5;
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--start-s must be inside the motion"), std::string::npos) << err;
  o = tiny_motion();
  o.render.gaze_px = glm::vec2(3, 3);
  EXPECT_EQ(run(o, &err), 2);
  EXPECT_NE(err.find("--gaze and --motion"), std::string::npos) << err;
}

TEST(RenderMotion, TinySequenceReportsPerRingTemporalNumbersForEveryVariant) {
  engine_test::TempDir dir;
  const MotionOptions o = tiny_motion_with_reference(dir.path, "off,restart,image");
  const auto j = run_json(o);
  ASSERT_FALSE(j.is_null());
  ASSERT_EQ(j["frames"].size(), 3u);
  EXPECT_NEAR(j["frames"][1]["time_s"].get<double>(), 0.5 + 1.0 / 70.0, 1e-12);
  // The head turns: every frame has its own pose.
  EXPECT_NE(j["frames"][0]["pose"], j["frames"][1]["pose"]);
  EXPECT_EQ(j["reference"]["spp"], 8);
  EXPECT_EQ(j["reference"]["rings"].size(), 7u);
  ASSERT_EQ(j["tracks"].size(), 4u);
  const std::vector<std::string> ids = {"full_spp1", "nearest_k1_s1_pixel-grid_r1_temporal-off",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-restart",
                                        "nearest_k1_s1_pixel-grid_r1_temporal-image"};
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto& t = j["tracks"][i];
    EXPECT_EQ(t["id"], ids[i]);
    EXPECT_EQ(t["frames"], 3);
    // Points traced per frame, the first frame's also as "points": at 64x72 px, every pixel.
    ASSERT_EQ(t["points_by_frame"].size(), 3u) << t["id"];
    EXPECT_EQ(t["points_by_frame"][0], t["points"]) << t["id"];
    for (const auto& p : t["points_by_frame"]) EXPECT_EQ(p, 64 * 72) << t["id"];
    // Primary rays per frame, the first frame's also in "rays": one a point at one ray per point.
    ASSERT_EQ(t["primary_rays_by_frame"].size(), 3u) << t["id"];
    EXPECT_EQ(t["primary_rays_by_frame"][0], t["rays"]["primary"]) << t["id"];
    for (const auto& r : t["primary_rays_by_frame"]) EXPECT_EQ(r, 64 * 72) << t["id"];
    ASSERT_EQ(t["rings"].size(), 7u);
    // Every ring, the fovea included, has pixels at 64x72.
    for (const auto& r : t["rings"]) {
      ASSERT_TRUE(r["flicker"].is_number()) << t["id"] << " " << r.dump();
      ASSERT_TRUE(r["flicker_tracked"].is_number()) << t["id"] << " " << r.dump();
      ASSERT_TRUE(r["psnr"].is_number()) << t["id"] << " " << r.dump();
      EXPECT_GT(r["flicker"].get<double>(), 0.0);
      EXPECT_GT(r["flicker_tracked"].get<double>(), 0.0);
      EXPECT_GT(r["psnr"].get<double>(), 5.0);
      EXPECT_LT(r["psnr"].get<double>(), 80.0);
    }
  }
  // At 64x72 px the pixel-exact point set is one point per pixel with the full
  // render's own jitter: off is the full render at 1 ray, frame by frame.
  EXPECT_EQ(j["tracks"][1]["rings"], j["tracks"][0]["rings"]);
  // The restarting history restarts on every frame of a moving head; reprojecting only on the first.
  EXPECT_EQ(j["tracks"][2]["temporal_resets"], 3);
  EXPECT_EQ(j["tracks"][3]["temporal_resets"], 1);
  // Equal rays: the foveated tracks trace the same points.
  EXPECT_EQ(j["tracks"][1]["rays"]["primary"], j["tracks"][3]["rays"]["primary"]);
  // Each track with history carries the goal against off, read from the two tracks' rings.
  EXPECT_FALSE(j["tracks"][0].contains("goal"));
  EXPECT_FALSE(j["tracks"][1].contains("goal"));
  for (const std::size_t i : {std::size_t(2), std::size_t(3)}) {
    const auto& goal = j["tracks"][i]["goal"];
    ASSERT_EQ(goal["flicker_tracked_ratio"].size(), 7u) << j["tracks"][i].dump();
    for (std::size_t r = 0; r < 7; ++r) {
      EXPECT_NEAR(goal["flicker_tracked_ratio"][r].get<double>(),
                  j["tracks"][1]["rings"][r]["flicker_tracked"].get<double>() /
                      j["tracks"][i]["rings"][r]["flicker_tracked"].get<double>(),
                  1e-12);
      EXPECT_NEAR(goal["psnr_minus_off_db"][r].get<double>(),
                  j["tracks"][i]["rings"][r]["psnr"].get<double>() - j["tracks"][1]["rings"][r]["psnr"].get<double>(),
                  1e-12);
    }
    EXPECT_TRUE(goal["peripheral_tracked_flicker_5x_lower"].is_boolean());
  }
  // Three frames of a 1-ray history are nowhere near 5x.
  EXPECT_FALSE(j["tracks"][3]["goal"]["peripheral_tracked_flicker_5x_lower"].get<bool>());
  // The reference sequence is cached: a second run renders none of it.
  const auto j2 = run_json(o);
  ASSERT_FALSE(j2.is_null());
  EXPECT_EQ(j2["reference"]["frames_from_cache"], 3);
  EXPECT_EQ(j2["tracks"][3]["rings"], j["tracks"][3]["rings"]);
}

// The reference sequence's own noise against every track's flicker and error, as the price list checks it: an
// 8-ray reference lies too close to a reprojected history, and the run says so; a 256-ray one lies 10 dB below
// 1-ray frames without history.
TEST(RenderMotion, AReferenceTooNoisyForTheSteadiestTrackIsSaid) {
  engine_test::TempDir dir;
  MotionOptions o = tiny_motion_with_reference(dir.path, "off,image");
  std::ostringstream out, err;
  ASSERT_EQ(run_motion(o, out, err), 0) << err.str();
  auto j = nlohmann::json::parse(out.str());
  ASSERT_TRUE(j.contains("sanity")) << j.dump();
  EXPECT_FALSE(j["sanity"]["floor_10db_below"].get<bool>());
  ASSERT_EQ(j["sanity"]["flicker_margin_db"].size(), 7u);
  double least = 1e9;
  for (const auto& m : j["sanity"]["flicker_margin_db"]) least = std::min(least, m.get<double>());
  EXPECT_LT(least, 10.0);
  EXPECT_NE(err.str().find("the reference's own noise lies only"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("--reference-spp"), std::string::npos) << err.str();

  o.temporal = "off";
  o.reference.spp = "256";
  std::ostringstream out2, err2;
  ASSERT_EQ(run_motion(o, out2, err2), 0) << err2.str();
  j = nlohmann::json::parse(out2.str());
  EXPECT_TRUE(j["sanity"]["floor_10db_below"].get<bool>()) << j["sanity"].dump();
  EXPECT_EQ(err2.str().find("the reference's own noise"), std::string::npos) << err2.str();
  // The text report says it too.
  o.render.json = false;
  std::ostringstream out3, err3;
  ASSERT_EQ(run_motion(o, out3, err3), 0) << err3.str();
  EXPECT_NE(out3.str().find("reference floor at least 10 dB below every track's flicker and error in every ring: yes"),
            std::string::npos)
      << out3.str();
  // Without a track with history there is no goal to read.
  EXPECT_EQ(out3.str().find("off over each track with history"), std::string::npos) << out3.str();
  o.temporal = "off,image";
  std::ostringstream out4, err4;
  ASSERT_EQ(run_motion(o, out4, err4), 0) << err4.str();
  EXPECT_NE(out4.str().find("off over each track with history"), std::string::npos) << out4.str();
  EXPECT_NE(out4.str().find("nearest_k1_s1_pixel-grid_r1_temporal-image: "), std::string::npos) << out4.str();
}

// --pixel-filter: the reference sequence, the full render and the foveated
// tracks all follow it; a bspline2 sequence renders its own references (it
// never reads the box ones from the cache) and says which filter it used. A
// filter the tool does not know is an error naming the option.
TEST(RenderMotion, PixelFilterReachesTheReferenceAndEveryTrack) {
  engine_test::TempDir dir;
  MotionOptions o = tiny_motion_with_reference(dir.path, "off,image");
  const auto box = run_json(o);
  ASSERT_FALSE(box.is_null());
  EXPECT_EQ(box["pixel_filter"], "box");
  o.render.pixel_filter = foveart::foveation::PixelFilter::bspline2;
  const auto j = run_json(o);
  ASSERT_FALSE(j.is_null());
  EXPECT_EQ(j["pixel_filter"], "bspline2");
  EXPECT_EQ(j["reference"]["frames_from_cache"], 0);
  ASSERT_EQ(j["tracks"].size(), box["tracks"].size());
  for (std::size_t t = 0; t < j["tracks"].size(); ++t)
    EXPECT_NE(j["tracks"][t]["rings"], box["tracks"][t]["rings"]) << j["tracks"][t]["id"];
  const auto again = run_json(o);
  ASSERT_FALSE(again.is_null());
  EXPECT_EQ(again["reference"]["frames_from_cache"], 3);

  std::string text;
  const int status = run_fovea_binary("motion --size 64x72 --pixel-filter gaussian", dir.path, &text);
  EXPECT_GT(status, 0) << text;
  EXPECT_NE(text.find("--pixel-filter: 'gaussian' is not box or bspline2"), std::string::npos) << text;
}

// --temporal-mean-while-young: the tracks with history and the history-fed-the-reference control
// blend a young history as the mean of its frames; the track without history and
// the reference are untouched.
TEST(RenderMotion, MeanWhileYoungReachesTheHistoryTracksAndTheirControl) {
  engine_test::TempDir dir;
  MotionOptions o = tiny_motion_with_reference(dir.path, "off,image");
  const auto exponential = run_json(o);
  ASSERT_FALSE(exponential.is_null());
  EXPECT_EQ(exponential["temporal_mean_while_young"], false);
  o.mean_while_young = true;
  const auto mean = run_json(o);
  ASSERT_FALSE(mean.is_null());
  EXPECT_EQ(mean["temporal_mean_while_young"], true);
  ASSERT_EQ(mean["tracks"].size(), exponential["tracks"].size());
  for (std::size_t t = 0; t < mean["tracks"].size(); ++t) {
    const auto& a = mean["tracks"][t];
    const bool history = a["temporal"] == "image";
    EXPECT_EQ(a["rings"] != exponential["tracks"][t]["rings"], history) << a["id"];
  }
  const auto& ring_mean = mean["reference"]["rings"][0];
  const auto& ring_exp = exponential["reference"]["rings"][0];
  EXPECT_EQ(ring_mean["psnr_floor"], ring_exp["psnr_floor"]);
  EXPECT_NE(ring_mean["history_on_reference_psnr"], ring_exp["history_on_reference_psnr"]);
}

// Across the saccade: every track reports its central and peripheral band frame
// by frame (frame 0 has no pair), the image history restarts on the first
// frame and at the saccade's onset, and the settled frames are the frames at
// least history_settle_frames after the motion's last restart, their pooled
// flicker within the range of their own frames'.
TEST(RenderMotion, BandsFrameByFrameAndTheSettledFramesAcrossASaccade) {
  engine_test::TempDir dir;
  MotionOptions o = tiny_motion_with_reference(dir.path, "off,image");
  o.render.mode = "foveated";
  o.render.frames = 24;
  o.start_s = 1.43;  // the built-in motion's saccade starts at 1.5 s
  const auto j = run_json(o);
  ASSERT_FALSE(j.is_null());
  ASSERT_EQ(j["frames"].size(), 24u);
  const int settle = j["reference"]["settle_frames"].get<int>();
  EXPECT_EQ(settle, 10);  // 1 / the layer's blend weight 0.1
  // The settled frames, from the frames' flags.
  std::vector<int> restarts, settled;
  int last_restart = 0;
  for (int t = 0; t < 24; ++t) {
    const auto& f = j["frames"][std::size_t(t)];
    if (t == 0 || f["saccade"].get<bool>() || f["blink"].get<bool>()) {
      last_restart = t;
      restarts.push_back(t);
    } else if (t - last_restart >= settle) {
      settled.push_back(t);
    }
  }
  ASSERT_GT(restarts.size(), 1u) << "the window holds the saccade";
  ASSERT_FALSE(settled.empty()) << "and frames after it settle";
  EXPECT_EQ(j["reference"]["settled_frames"], settled.size());
  // The image history restarts on the first frame and the saccade's first.
  EXPECT_EQ(j["tracks"][1]["temporal_reset_frames"], nlohmann::json::array({0, restarts[1]}));
  EXPECT_EQ(j["tracks"][1]["temporal_resets"], 2);
  for (const auto* owner : {&j["tracks"][0]["bands"], &j["tracks"][1]["bands"],
                            &j["reference"]["history_on_reference_bands"], &j["reference"]["stable_blur_bands"]}) {
    ASSERT_EQ(owner->size(), 2u);
    EXPECT_EQ((*owner)[0]["band"], "centre");
    EXPECT_EQ((*owner)[0]["to_deg"], 5.0);
    EXPECT_EQ((*owner)[1]["band"], "periphery");
    EXPECT_EQ((*owner)[1]["from_deg"], 20.0);
    EXPECT_TRUE((*owner)[1]["to_deg"].is_null());
    for (const auto& band : *owner) {
      for (const char* key : {"flicker_by_frame", "flicker_tracked_by_frame", "psnr_by_frame"})
        ASSERT_EQ(band[key].size(), 24u) << key;
      EXPECT_TRUE(band["flicker_by_frame"][0].is_null());
      EXPECT_TRUE(band["psnr_by_frame"][1].is_number());
      for (const char* measure : {"flicker", "flicker_tracked"}) {
        double lo = INFINITY, hi = -INFINITY;
        for (int t : settled) {
          const double v = band[std::string(measure) + "_by_frame"][std::size_t(t)].get<double>();
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
        const double pooled = band["settled"][measure].get<double>();
        EXPECT_GE(pooled, lo * (1 - 1e-9)) << band["band"] << " " << measure;
        EXPECT_LE(pooled, hi * (1 + 1e-9)) << band["band"] << " " << measure;
      }
    }
  }
  // The history fed the reference starts from the reference itself: no error (an infinite PSNR is null).
  EXPECT_TRUE(j["reference"]["history_on_reference_bands"][1]["psnr_by_frame"][0].is_null());
  EXPECT_TRUE(j["tracks"][1]["bands"][1]["psnr_by_frame"][0].is_number());
  // The restart shows the raw frame: the image history's peripheral flicker
  // jumps at the saccade's onset above its settled level.
  const auto& reproject = j["tracks"][1]["bands"][1];
  EXPECT_GT(reproject["flicker_tracked_by_frame"][std::size_t(restarts[1])].get<double>(),
            reproject["settled"]["flicker_tracked"].get<double>());
}
