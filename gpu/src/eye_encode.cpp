// Stage 6 of an eye's device frame: the display transform and 8-bit (sRGB)
// encode into the shown image (skipped on the device when the frame slot's
// status says the trace failed), and the copy of the shown image into the
// swapchain image.
#include "foveation/display_transform.hpp"
#include "gpu/eye.hpp"
#include "gpu/shader_interface/encode.h"
#include "gpu/vk_util.hpp"

namespace foveart::gpu {
namespace {

using shader::EncodePush;

}  // namespace

void Eye::record_encode(VkCommandBuffer cb, const EyeFrame& frame, VkImage image) {
  const EncodePush e{{int32_t(width_px_), int32_t(height_px_)},
                     frame.srgb ? 1u : 0u,
                     frame.display.exposure,
                     foveation::tone_map_shader_id(frame.display.tone_map)};
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines_.encode());
  vkCmdPushConstants(cb, pipelines_.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof e, &e);
  vkCmdDispatch(cb, (width_px_ + 7) / 8, (height_px_ + 7) / 8, 1);
  memory_barrier(cb, kCompute, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  if (image != VK_NULL_HANDLE) record_copy_to_image(cb, shown_.buffer, image, width_px_, height_px_);
  stamp(cb, 5);
}

}  // namespace foveart::gpu
