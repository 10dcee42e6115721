// The scene's textures as sampled images for set 0, binding 6 of the tracers
// (scene_data.glsl's scene_textures[kTextureSlots]): one VkImage per texture a
// material samples, in device-local memory (MemoryLedger) filled through staging.
//
// Format: RGBA8 holding the sRGB bytes where every texel is what the glTF loader
// decodes from an 8-bit sRGB image (srgb_to_linear(v / 255) for colour, v / 255
// for alpha: re-encoding gives the bytes back exactly), 4 bytes a texel. Any
// other texture (procedural floats, 16-bit PNGs) is RGBA32F, so its texels stay
// what the CPU engine reads. Level 0 is what the CPU engine samples; a full mip
// chain follows (texture_mips.hpp: 2x2 box filters in linear values, re-encoded
// to sRGB bytes for RGBA8), sampled where a ray brings its footprint.
//
// Decoding and filtering: the shaders fetch texels and decode, wrap and filter
// them in float with the glTF wrap modes and filter (GpuMaterial::texture_flags),
// as the loader and texture_sampler.hpp do. Measured on lavapipe, an
// R8G8B8A8_SRGB view's own decode is up to 1.8 % off the CPU engine's in dark
// texels (sampled or fetched), past the per-ray tolerance: hence UNORM and the
// decode in the shader (and the shader's own filtering between levels). The
// sampler only has to be valid (nearest, clamp).
//
// Slots: shaders index the array only with constants (lavapipe offers no
// descriptor indexing), so it has a fixed size; unused slots hold a 1x1 texture.
#pragma once

#include "vk_buffer.hpp"

#include <engine/scene.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

inline constexpr uint32_t kTextureSlots = 32;  // scene_data.glsl's scene_textures[32]

class SceneTextures {
 public:
  SceneTextures() = default;
  ~SceneTextures();
  SceneTextures(const SceneTextures&) = delete;
  SceneTextures& operator=(const SceneTextures&) = delete;

  // The textures scene.textures[used[i]] into slots i (at most kTextureSlots), then the placeholder.
  [[nodiscard]] bool create(const std::shared_ptr<MemoryLedger>& ledger, Uploader& uploader, const engine::Scene& scene,
                            const std::vector<uint32_t>& used, std::string* error);
  void destroy();

  // For vkUpdateDescriptorSets: every slot, in SHADER_READ_ONLY_OPTIMAL.
  const std::array<VkDescriptorImageInfo, kTextureSlots>& descriptors() const { return descriptors_; }
  uint32_t count() const { return count_; }   // slots holding scene textures
  bool srgb8(uint32_t slot) const {  // RGBA8 holding sRGB bytes (else RGBA32F, linear)
    for (uint32_t s : srgb8_)
      if (s == slot) return true;
    return false;
  }

 private:
  struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    MemoryLedger::Allocation memory;
  };
  struct MipUpload {  // a level past 0: its size and texels, in the image's format
    uint32_t width, height;
    const void* texels;
  };
  bool add_image(Uploader& uploader, uint32_t width, uint32_t height, VkFormat format, const void* texels,
                 uint32_t texel_bytes, std::string* error, const std::vector<MipUpload>& mips = {});
  bool add_texture(Uploader& uploader, const engine::Texture& t, uint32_t slot, std::string* error);
  VkSampler sampler(std::string* error);

  std::shared_ptr<MemoryLedger> ledger_;
  std::vector<Image> images_;
  VkSampler sampler_ = VK_NULL_HANDLE;
  std::array<VkDescriptorImageInfo, kTextureSlots> descriptors_{};
  uint32_t count_ = 0;
  std::vector<uint32_t> srgb8_;  // slots
};

}  // namespace foveart::gpu_engine
