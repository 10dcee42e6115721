// Every compute pipeline of a device frame, made once per device and shared
// by its eyes: the reconstruction set's (scatter, gather, temporal, encode:
// shaders/common.glsl's one descriptor set and their push constants), the
// render cache's and, at the first device-traced frame, the device trace's.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>

#include <vulkan/vulkan.h>

#include "gpu/device_trace.hpp"
#include "gpu/ray_cache.hpp"
#include "gpu/shader_interface/encode.h"
#include "gpu/shader_interface/gather.h"
#include "gpu/shader_interface/scatter.h"
#include "gpu/shader_interface/temporal.h"
#include "gpu/table_pack.hpp"

namespace foveart::gpu {

// The reconstruction set's bindings (shaders/common.glsl): the table chunks'
// array, then one buffer per binding.
enum FrameBinding : uint32_t {
  kChunksBinding = 0,
  kColorsBinding,
  kCurrentBinding,
  kHistoryInBinding,
  kHistoryOutBinding,
  kUploadBinding,
  kEncodedBinding,  // the shown image (RGBA8), written by good frames only
  kPointDepthBinding,
  kStatusBinding,  // the frame slot's status (shader_interface/device_trace.h)
  kFrameBindings
};
inline constexpr uint32_t kFrameDescriptorCounts[kFrameBindings] = {uint32_t(kMaxTableChunks), 1, 1, 1, 1, 1, 1, 1, 1};
inline constexpr uint32_t kFrameStorageBuffers = uint32_t(kMaxTableChunks) + kFrameBindings - 1;
// The set's push-constant range: the largest of its shaders' blocks.
inline constexpr uint32_t kFramePushBytes = uint32_t(
    std::max({sizeof(shader::ScatterPush), sizeof(shader::GatherPush), sizeof(shader::TemporalPush),
              sizeof(shader::EncodePush)}));

class FramePipelines {
 public:
  static std::unique_ptr<FramePipelines> create(VkDevice device, std::string* error);
  ~FramePipelines();
  FramePipelines(const FramePipelines&) = delete;
  FramePipelines& operator=(const FramePipelines&) = delete;

  VkDescriptorSetLayout set_layout() const { return set_layout_; }
  VkPipelineLayout layout() const { return layout_; }
  VkPipeline scatter() const { return scatter_; }
  VkPipeline gather() const { return gather_; }
  VkPipeline temporal() const { return temporal_; }
  VkPipeline encode() const { return encode_; }
  const RayCachePipelines& ray_cache() const { return *ray_cache_; }
  // The device trace's pipelines, made at the first call; null with *error where they cannot run.
  const DeviceTracePipelines* device_trace(std::string* error) const;

 private:
  FramePipelines() = default;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline scatter_ = VK_NULL_HANDLE, gather_ = VK_NULL_HANDLE, temporal_ = VK_NULL_HANDLE, encode_ = VK_NULL_HANDLE;
  std::unique_ptr<RayCachePipelines> ray_cache_;
  mutable std::unique_ptr<DeviceTracePipelines> device_trace_;  // one thread at a time, as every stage
};

}  // namespace foveart::gpu
