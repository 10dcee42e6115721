// SceneTextures: format choice (exact sRGB8 or float), images through staging,
// the placeholder for unused slots.
#include "scene_textures.hpp"
#include "texture_mips.hpp"
#include "vk_helpers.hpp"

#include <foveation/srgb.hpp>

#include <algorithm>
#include <array>
#include <cstring>

namespace foveart::gpu_engine {
namespace {

// The loader's decode of every 8-bit value (gltf_loader.cpp: srgb_to_linear(v / 255.0f)).
const std::array<float, 256>& srgb8_decode() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int v = 0; v < 256; ++v) t[v] = foveation::srgb_to_linear(static_cast<float>(v) / 255.0f);
    return t;
  }();
  return table;
}

// The 8-bit code whose decode is exactly `c`, or -1.
int exact_code(float c, bool srgb) {
  int v = srgb ? foveation::encode_srgb8(c) : static_cast<int>(c * 255.0f + 0.5f);
  if (!(v >= 0 && v <= 255)) return -1;  // NaN, out of range
  for (int d : {0, -1, 1}) {
    const int w = v + d;
    if (w < 0 || w > 255) continue;
    const float back = srgb ? srgb8_decode()[w] : static_cast<float>(w) / 255.0f;
    if (back == c) return w;
  }
  return -1;
}

// RGBA8 sRGB texels of `t` when they give its texels back exactly; empty otherwise.
std::vector<uint8_t> exact_srgb8(const engine::Texture& t) {
  std::vector<uint8_t> out(t.texels.size() * 4);
  for (size_t i = 0; i < t.texels.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      const int v = exact_code(t.texels[i][k], k < 3);
      if (v < 0) return {};
      out[4 * i + k] = static_cast<uint8_t>(v);
    }
  }
  return out;
}

// Level texels as RGBA8 holding sRGB bytes (rgb encoded, alpha linear), as level 0 of an srgb8 texture.
std::vector<uint8_t> srgb8_level(const std::vector<glm::vec4>& texels) {
  std::vector<uint8_t> out(texels.size() * 4);
  for (size_t i = 0; i < texels.size(); ++i) {
    for (int k = 0; k < 3; ++k) out[4 * i + k] = foveation::encode_srgb8(texels[i][k]);
    out[4 * i + 3] = static_cast<uint8_t>(std::clamp(texels[i].w, 0.0f, 1.0f) * 255.0f + 0.5f);
  }
  return out;
}

}  // namespace

SceneTextures::~SceneTextures() { destroy(); }

void SceneTextures::destroy() {
  if (ledger_ == nullptr) return;
  const VkDevice d = ledger_->device();
  for (Image& i : images_) {
    if (i.view != VK_NULL_HANDLE) vkDestroyImageView(d, i.view, nullptr);
    if (i.image != VK_NULL_HANDLE) vkDestroyImage(d, i.image, nullptr);
    ledger_->release(&i.memory);
  }
  if (sampler_ != VK_NULL_HANDLE) vkDestroySampler(d, sampler_, nullptr);
  sampler_ = VK_NULL_HANDLE;
  images_.clear();
  ledger_.reset();
}

// The one sampler: the shaders fetch texels (texelFetch, any level) and filter
// them themselves, so it only has to be valid: nearest, clamped.
VkSampler SceneTextures::sampler(std::string* error) {
  if (sampler_ != VK_NULL_HANDLE) return sampler_;
  VkSamplerCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
  info.magFilter = info.minFilter = VK_FILTER_NEAREST;
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  info.maxLod = VK_LOD_CLAMP_NONE;
  const VkResult r = vkCreateSampler(ledger_->device(), &info, nullptr, &sampler_);
  if (r != VK_SUCCESS) {
    sampler_ = VK_NULL_HANDLE;
    fail(error, vk_error("vkCreateSampler", r));
  }
  return sampler_;
}

// One sampled image, its memory from the ledger, level 0 and then `mips` (levels 1..) uploaded, and its view.
bool SceneTextures::add_image(Uploader& uploader, uint32_t width, uint32_t height, VkFormat format,
                              const void* texels, uint32_t texel_bytes, std::string* error,
                              const std::vector<MipUpload>& mips) {
  const VkDevice d = ledger_->device();
  images_.emplace_back();
  Image& img = images_.back();
  VkImageCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1 + static_cast<uint32_t>(mips.size());
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkResult r = vkCreateImage(d, &info, nullptr, &img.image);
  if (r != VK_SUCCESS) {
    img.image = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateImage", r) + " for a " + std::to_string(width) + "x" +
                           std::to_string(height) + " texture");
  }
  VkMemoryRequirements req{};
  vkGetImageMemoryRequirements(d, img.image, &req);
  if (!ledger_->allocate(req, false, true, &img.memory, error)) return false;
  r = vkBindImageMemory(d, img.image, img.memory.memory, 0);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkBindImageMemory", r));
  if (!uploader.image(img.image, width, height, texel_bytes, texels, error)) return false;
  for (uint32_t k = 0; k < mips.size(); ++k) {
    if (!uploader.image(img.image, mips[k].width, mips[k].height, texel_bytes, mips[k].texels, error, k + 1))
      return false;
  }
  VkImageViewCreateInfo view{};
  view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
  view.image = img.image;
  view.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view.format = format;
  view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, info.mipLevels, 0, 1};
  r = vkCreateImageView(d, &view, nullptr, &img.view);
  if (r != VK_SUCCESS) {
    img.view = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateImageView", r));
  }
  return true;
}

// Texture `t` with its mip chain, RGBA8 sRGB where level 0 is exact that way, else RGBA32F.
bool SceneTextures::add_texture(Uploader& uploader, const engine::Texture& t, uint32_t slot, std::string* error) {
  const std::vector<MipLevel> chain = box_mip_chain(t);
  const std::vector<uint8_t> srgb = exact_srgb8(t);
  std::vector<std::vector<uint8_t>> srgb_levels;  // what the uploads point at
  std::vector<MipUpload> mips;
  for (const MipLevel& level : chain) {
    if (!srgb.empty()) srgb_levels.push_back(srgb8_level(level.texels));
    mips.push_back({level.width, level.height,
                    srgb.empty() ? static_cast<const void*>(level.texels.data()) : srgb_levels.back().data()});
  }
  if (srgb.empty()) {
    return add_image(uploader, t.width, t.height, VK_FORMAT_R32G32B32A32_SFLOAT, t.texels.data(), 16, error, mips);
  }
  srgb8_.push_back(slot);
  return add_image(uploader, t.width, t.height, VK_FORMAT_R8G8B8A8_UNORM, srgb.data(), 4, error, mips);
}

bool SceneTextures::create(const std::shared_ptr<MemoryLedger>& ledger, Uploader& uploader, const engine::Scene& scene,
                           const std::vector<uint32_t>& used, std::string* error) {
  destroy();
  ledger_ = ledger;
  if (used.size() > kTextureSlots)
    return fail(error, scene.source + ": the materials sample " + std::to_string(used.size()) +
                           " textures; the GPU engine binds at most " + std::to_string(kTextureSlots));
  const VkSampler s = sampler(error);
  if (s == VK_NULL_HANDLE) return false;
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(ledger->physical_device(), &props);
  for (uint32_t slot = 0; slot < used.size(); ++slot) {
    const engine::Texture& t = scene.textures[used[slot]];
    if (t.width > props.limits.maxImageDimension2D || t.height > props.limits.maxImageDimension2D)
      return fail(error, scene.source + ": texture " + std::to_string(used[slot]) + " (" + std::to_string(t.width) +
                             "x" + std::to_string(t.height) + ") exceeds the device's maxImageDimension2D (" +
                             std::to_string(props.limits.maxImageDimension2D) + ")");
    if (!add_texture(uploader, t, slot, error)) return false;
    descriptors_[slot] = VkDescriptorImageInfo{s, images_.back().view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  }
  count_ = static_cast<uint32_t>(used.size());
  // The placeholder: one opaque white texel for the slots no material samples.
  const uint8_t texel[4] = {255, 255, 255, 255};
  if (!add_image(uploader, 1, 1, VK_FORMAT_R8G8B8A8_UNORM, texel, 4, error)) return false;
  for (uint32_t slot = count_; slot < kTextureSlots; ++slot)
    descriptors_[slot] = VkDescriptorImageInfo{s, images_.back().view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  return true;
}

}  // namespace foveart::gpu_engine
