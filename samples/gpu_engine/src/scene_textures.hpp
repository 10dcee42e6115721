// The scene's textures as sampled images for set 0, binding 6 of the tracers
// (scene_data.glsl's scene_textures[kTextureSlots]): one VkImage per texture a
// material samples, in device-local memory (MemoryLedger) filled through
// staging, with a VkSampler for its glTF wrap modes and filter.
//
// Format: VK_FORMAT_R8G8B8A8_SRGB where every texel is what the glTF loader
// decodes from an 8-bit sRGB image (srgb_to_linear(v / 255) for colour, v / 255
// for alpha: the sRGB encoding gives it back exactly); the sampler then decodes
// before it filters, as the CPU engine does (it decodes at load, then filters).
// Any other texture (procedural floats, 16-bit PNGs) as RGBA32F (RGBA16F where
// the device cannot filter that), so its texels stay what the CPU engine reads.
// One level, no mips: the CPU engine samples level 0 (texture_sampler.hpp).
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
  uint32_t srgb8_count() const { return srgb8_; }  // of which RGBA8 sRGB

 private:
  struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    MemoryLedger::Allocation memory;
  };
  bool add_image(Uploader& uploader, uint32_t width, uint32_t height, VkFormat format, const void* texels,
                 uint32_t texel_bytes, std::string* error);
  VkSampler sampler(const engine::Texture& t, std::string* error);

  std::shared_ptr<MemoryLedger> ledger_;
  std::vector<Image> images_;
  std::vector<std::pair<uint32_t, VkSampler>> samplers_;  // (wrap_s | wrap_t << 2 | nearest << 4, sampler)
  std::array<VkDescriptorImageInfo, kTextureSlots> descriptors_{};
  uint32_t count_ = 0;
  uint32_t srgb8_ = 0;
};

}  // namespace foveart::gpu_engine
