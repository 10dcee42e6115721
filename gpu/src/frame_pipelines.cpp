#include "gpu/frame_pipelines.hpp"

#include "gpu/vk_util.hpp"
#include "shaders/encode.spv.h"
#include "shaders/gather.spv.h"
#include "shaders/scatter.spv.h"
#include "shaders/temporal.spv.h"

namespace foveart::gpu {

std::unique_ptr<FramePipelines> FramePipelines::create(VkDevice device, std::string* error) {
  std::unique_ptr<FramePipelines> p(new FramePipelines());
  p->device_ = device;
  if (!create_storage_pipeline_layout(device, kFrameDescriptorCounts, kFrameBindings, kFramePushBytes,
                                      &p->set_layout_, &p->layout_, error)) {
    return nullptr;
  }
  struct Stage {
    const uint32_t* code;
    size_t bytes;
    VkPipeline* pipeline;
  };
  const Stage stages[] = {{foveart_scatter_spv, sizeof foveart_scatter_spv, &p->scatter_},
                          {foveart_gather_spv, sizeof foveart_gather_spv, &p->gather_},
                          {foveart_temporal_spv, sizeof foveart_temporal_spv, &p->temporal_},
                          {foveart_encode_spv, sizeof foveart_encode_spv, &p->encode_}};
  for (const Stage& s : stages) {
    if (!create_compute_pipeline(device, p->layout_, s.code, s.bytes, s.pipeline, error)) return nullptr;
  }
  p->ray_cache_ = RayCachePipelines::create(device, error);
  if (p->ray_cache_ == nullptr) return nullptr;
  return p;
}

const DeviceTracePipelines* FramePipelines::device_trace(std::string* error) const {
  if (device_trace_ == nullptr) device_trace_ = DeviceTracePipelines::create(device_, error);
  return device_trace_.get();
}

FramePipelines::~FramePipelines() {
  for (VkPipeline p : {scatter_, gather_, temporal_, encode_})
    if (p != VK_NULL_HANDLE) vkDestroyPipeline(device_, p, nullptr);
  if (layout_ != VK_NULL_HANDLE) vkDestroyPipelineLayout(device_, layout_, nullptr);
  if (set_layout_ != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
}

}  // namespace foveart::gpu
