// Large textures on the GPU engine: a glTF with five 2048x2048 PNG base colour
// textures (written at test time) renders on the device as on the CPU engine,
// per eccentricity ring, with its textures as sampled images in device-local
// memory. Runs on lavapipe.
#include <gpu_engine/gpu_tracer.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/render.hpp>
#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/eye_rays.hpp>
#include <foveation/srgb.hpp>

#include "gltf_fixtures.hpp"
#include "gpu_trace_fixtures.hpp"
#include "ring_compare.hpp"

#include <stb_image_write.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

using foveart::engine::Scene;
using foveart::gpu_engine::GpuTracer;
using foveart::layer::DevicePreference;
using foveart::layer::test::kRingEdgesDeg;
using foveart::layer::test::kRings;
using namespace foveart::gpu_engine::testing;

constexpr int kSide = 2048;
constexpr int kTextures = 5;

TestGpu& texture_gpu() {
  static TestGpu g(DevicePreference::cpu, false);
  return g;
}

// Texture k: smooth colour waves (periods of hundreds of texels, so the view's
// minification does not alias), different per texture. RGB, 8 bits.
std::vector<uint8_t> wave_texels(int k) {
  std::vector<uint8_t> by_x(kSide), by_y(kSide), by_sum(2 * kSide);
  constexpr double kTau = 6.283185307179586;
  for (int i = 0; i < kSide; ++i) {
    by_x[i] = static_cast<uint8_t>(127.5 + 127.0 * std::sin(kTau * (i / 512.0 + k / 5.0)));
    by_y[i] = static_cast<uint8_t>(127.5 + 127.0 * std::sin(kTau * (i / (384.0 + 64.0 * k))));
  }
  for (int i = 0; i < 2 * kSide; ++i) by_sum[i] = static_cast<uint8_t>(127.5 + 127.0 * std::cos(kTau * (i / 700.0 + k)));
  std::vector<uint8_t> px(size_t{kSide} * kSide * 3);
  for (int y = 0; y < kSide; ++y)
    for (int x = 0; x < kSide; ++x) {
      uint8_t* p = px.data() + (size_t(y) * kSide + x) * 3;
      p[0] = by_x[x];
      p[1] = by_y[y];
      p[2] = by_sum[x + y];
    }
  return px;
}

// Five 2 x 4 m panels in a row at z = 0 facing +z, each with its own texture and
// material; the first three with uvs over [-0.25, 1.25] and wrap modes repeat,
// clamp, mirror. A camera at z = 3 looking down -z, a directional light along -z.
std::filesystem::path write_five_textures(const std::filesystem::path& dir) {
  engine_test::GltfDoc doc;
  doc.json = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"buffers", {nlohmann::json::object()}},
              {"bufferViews", nlohmann::json::array()}, {"accessors", nlohmann::json::array()},
              {"extensionsUsed", {"KHR_lights_punctual"}},
              {"extensions", {{"KHR_lights_punctual", {{"lights", {{{"type", "directional"}, {"intensity", 3.0}}}}}}}},
              {"cameras", {{{"type", "perspective"}, {"perspective", {{"yfov", 1.2}, {"znear", 0.05}}}}}}};
  nlohmann::json primitives = nlohmann::json::array();
  auto add = [&](const auto& values, const char* type, int count) {
    std::vector<uint8_t> b(values.size() * sizeof(values[0]));
    std::memcpy(b.data(), values.data(), b.size());
    doc.json["accessors"].push_back({{"bufferView", engine_test::add_view(doc, b)},
                                     {"componentType", sizeof(values[0]) == 4 ? 5126 : 5123},
                                     {"count", count}, {"type", type}});
    return static_cast<int>(doc.json["accessors"].size() - 1);
  };
  const int wraps[kTextures] = {10497, 33071, 33648, 10497, 10497};
  for (int k = 0; k < kTextures; ++k) {
    const float x0 = -5.4f + 2.2f * static_cast<float>(k), lo = k < 3 ? -0.25f : 0.0f, hi = k < 3 ? 1.25f : 1.0f;
    const int pos = add(std::vector<float>{x0, -2, 0, x0 + 2, -2, 0, x0 + 2, 2, 0, x0, 2, 0}, "VEC3", 4);
    doc.json["accessors"][pos]["min"] = {x0, -2, 0};
    doc.json["accessors"][pos]["max"] = {x0 + 2, 2, 0};
    const int nrm = add(std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 4);
    const int uv = add(std::vector<float>{lo, hi, hi, hi, hi, lo, lo, lo}, "VEC2", 4);
    const int idx = add(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, "SCALAR", 6);
    primitives.push_back({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}}},
                          {"indices", idx}, {"material", k}});
    const std::string png = "wave" + std::to_string(k) + ".png";
    const std::vector<uint8_t> px = wave_texels(k);
    stbi_write_png_compression_level = 1;  // fast: the test reads them once
    if (stbi_write_png((dir / png).string().c_str(), kSide, kSide, 3, px.data(), kSide * 3) == 0) return {};
    doc.json["images"].push_back({{"uri", png}});
    doc.json["samplers"].push_back({{"magFilter", 9729}, {"minFilter", 9729}, {"wrapS", wraps[k]}, {"wrapT", wraps[k]}});
    doc.json["textures"].push_back({{"source", k}, {"sampler", k}});
    doc.json["materials"].push_back(
        {{"pbrMetallicRoughness",
          {{"baseColorTexture", {{"index", k}}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}});
  }
  doc.json["meshes"] = {{{"primitives", primitives}}};
  doc.json["nodes"] = {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0.0, 0.0, 3.0}}},
                       {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}};
  doc.json["scenes"] = {{{"nodes", {0, 1, 2}}}};
  return engine_test::write_external(dir, "five_textures", std::move(doc));
}

// render_full on the CPU engine: rgb and the first ray's depth per pixel.
std::vector<glm::vec4> render_cpu(foveart::engine::Tracer& tracer, const FoveartEyeView& view, uint32_t spp,
                                  uint64_t seed) {
  foveart::foveation::ImageRgb image(1, 1);
  std::vector<float> depth;
  foveart::engine::RenderSettings settings;
  settings.spp = spp;
  settings.seed = seed;
  settings.out_depth_m = &depth;
  foveart::foveation::Executor executor(2);
  EXPECT_EQ(foveart::engine::render_full(foveart_engine_trace_rays, &tracer, view, settings, &image, executor).status,
            FOVEART_RESULT_SUCCESS);
  std::vector<glm::vec4> out(size_t{view.width_px} * view.height_px);
  for (size_t i = 0; i < out.size() && 3 * i + 2 < image.rgb.size() && i < depth.size(); ++i)
    out[i] = glm::vec4(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2], depth[i]);
  return out;
}

std::vector<glm::vec4> render_gpu(GpuTracer& tracer, const FoveartEyeView& view, uint32_t spp, uint64_t seed) {
  const size_t pixels = size_t{view.width_px} * view.height_px;
  HostBuffer out(texture_gpu(), 16 * pixels);
  std::string error;
  EXPECT_TRUE(texture_gpu().run([&](VkCommandBuffer cb) {
    const bool ok = tracer.record_full(cb, view, spp, seed, out.buffer, 0, &error);
    layer_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT);
    return ok;
  })) << error;
  std::vector<glm::vec4> px(pixels);
  std::memcpy(px.data(), out.data, 16 * pixels);
  return px;
}

// Linear radiance -> 8 bits, both images scaled alike (the CPU image's brightest channel -> 1).
foveart::layer::test::Rgb8 to_rgb8(const std::vector<glm::vec4>& px, const FoveartEyeView& view, float scale) {
  foveart::layer::test::Rgb8 img;
  img.width = static_cast<int>(view.width_px);
  img.height = static_cast<int>(view.height_px);
  for (const glm::vec4& p : px)
    for (int c = 0; c < 3; ++c) img.rgb.push_back(foveart::foveation::encode_srgb8(p[c] * scale));
  return img;
}

std::vector<double> fov_of(const FoveartEyeView& v) {
  return {v.angle_left_rad, v.angle_right_rad, v.angle_up_rad, v.angle_down_rad};
}

// Per ring of eccentricity from the view's centre (ring_compare.hpp's rings):
// every ray within kRayTolerance of the CPU engine's, depth too.
void expect_rays_agree_per_ring(const std::vector<glm::vec4>& gpu_px, const std::vector<glm::vec4>& cpu_px,
                                const FoveartEyeView& view) {
  std::array<std::vector<glm::vec4>, kRings> g, c;
  const std::vector<double> fov = fov_of(view);
  const int w = static_cast<int>(view.width_px), h = static_cast<int>(view.height_px);
  const auto centre = foveart::layer::test::pixel_direction(fov, w, h, w / 2 + 0.5, h / 2 + 0.5);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto d = foveart::layer::test::pixel_direction(fov, w, h, x + 0.5, y + 0.5);
      const double cosine = std::clamp(d[0] * centre[0] + d[1] * centre[1] + d[2] * centre[2], -1.0, 1.0);
      const double deg = std::acos(cosine) * 180.0 / 3.14159265358979323846;
      int r = 0;
      while (r + 1 < kRings && deg >= kRingEdgesDeg[r + 1]) ++r;
      g[r].push_back(gpu_px[size_t(y) * w + x]);
      c[r].push_back(cpu_px[size_t(y) * w + x]);
    }
  for (int r = 0; r < kRings; ++r) {
    const std::string what = "ring " + std::to_string(kRingEdgesDeg[r]).substr(0, 4) + "-" +
                             std::to_string(kRingEdgesDeg[r + 1]).substr(0, 6) + " deg";
    EXPECT_FALSE(c[r].empty()) << what;
    expect_agreement(compare(g[r], c[r]), what.c_str());
  }
}

}  // namespace

TEST(GpuTextures, FiveTextures2048MatchTheCpuEnginePerRing) {
  if (!texture_gpu().vk.ok()) GTEST_SKIP() << "no Vulkan device";
  engine_test::TempDir dir;
  const std::filesystem::path file = write_five_textures(dir.path);
  ASSERT_FALSE(file.empty()) << "writing the PNGs failed";
  foveart::engine::LoadResult loaded = foveart::engine::load_gltf(file.string());
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  ASSERT_EQ(loaded.scene->textures.size(), size_t{kTextures});
  for (const auto& t : loaded.scene->textures) ASSERT_TRUE(t.width == kSide && t.height == kSide);
  FoveartEyeView view = foveart::engine::fove_eye_view(0, foveart::engine::scene_head(*loaded.scene));
  view.width_px = 160;  // the FOVE frustum at a small size
  view.height_px = 180;

  std::string error;
  auto g = GpuTracer::create(texture_gpu().context(), *loaded.scene, {}, &error);
  ASSERT_NE(g, nullptr) << error;  // was: "scene buffer 7 (335544320 bytes) exceeds maxStorageBufferRange"
  const foveart::gpu_engine::MemoryUse m = g->memory_use();
  std::printf("[ memory ] five 2048x2048 textures: device-local %llu bytes, host-visible %llu bytes, textures %llu "
              "bytes\n", static_cast<unsigned long long>(m.device_local_bytes),
              static_cast<unsigned long long>(m.host_visible_bytes), static_cast<unsigned long long>(m.texture_bytes));
  EXPECT_EQ(g->memory_fallback(), "");
  EXPECT_GE(m.texture_bytes, uint64_t{kTextures} * kSide * kSide * 4);  // RGBA8 sRGB: 4 bytes a texel
  EXPECT_LT(m.texture_bytes, uint64_t{kTextures} * kSide * kSide * 8);  // not RGBA32F
  EXPECT_GE(m.device_local_bytes, m.texture_bytes);

  foveart::engine::TracerOptions options;
  auto c = foveart::engine::Tracer::create(std::move(*loaded.scene), options, &error);
  ASSERT_NE(c, nullptr) << error;
  constexpr uint32_t kSpp = 1;
  constexpr uint64_t kSeed = 0x5eed;
  const std::vector<glm::vec4> cpu_px = render_cpu(*c, view, kSpp, kSeed);
  const std::vector<glm::vec4> gpu_px = render_gpu(*g, view, kSpp, kSeed);

  size_t hits = 0;
  float brightest = 0.0f;
  for (const glm::vec4& p : cpu_px) {
    hits += std::isfinite(p.w) ? 1 : 0;
    brightest = std::max({brightest, p.r, p.g, p.b});
  }
  EXPECT_GT(hits, cpu_px.size() / 4) << "the panels fill the view";
  ASSERT_GT(brightest, 0.0f);
  expect_agreement(compare(gpu_px, cpu_px), "five 2048x2048 textures, 160x180");
  expect_rays_agree_per_ring(gpu_px, cpu_px, view);
  const auto rings = foveart::layer::test::compare_rings(to_rgb8(gpu_px, view, 1.0f / brightest),
                                                         to_rgb8(cpu_px, view, 1.0f / brightest), fov_of(view),
                                                         view.width_px / 2, view.height_px / 2);
  foveart::layer::test::print_rings("[ rings ] 8-bit", rings);
  for (int r = 0; r < kRings; ++r) EXPECT_TRUE(rings[r].passes()) << "ring " << r;
  expect_no_validation_errors(texture_gpu());
}
