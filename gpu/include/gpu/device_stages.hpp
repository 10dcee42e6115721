// The device's stage set (foveation/frame_stages.hpp, docs/gpu.md "One frame
// in stages"): the same stage interfaces as the CPU's, recorded into one
// eye's frame on the device (gpu::Eye's stages) instead of run on host images.
// foveation::FoveatedView runs either set; the layer picks one per eye.
//
//   1-3  DeviceTraceStage: the engine's device trace and resolve (device_trace.hpp), or
//        UploadedTrace: the engine's callback on the CPU (CallbackTrace), its colours uploaded
//   4    DeviceGather: scatter + gather
//   5    DeviceHistory: the host's history decides (TemporalHistory::decide), the device
//        applies it (the image history, or the render cache)
//   6    DeviceEncode: display transform, encode, the copy into the swapchain image
//
// The frame's resources are a DeviceFrame: the eye, its tables, the frame
// slot, the swapchain image and the command buffer, begun by the first stage
// that records. Nothing here throws for what the device does; a stage that
// cannot record fails the frame with a message (FrameFailure::resources_failed,
// or callback_failed when the engine's device trace failed).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <vulkan/vulkan.h>

#include "foveation/display_transform.hpp"
#include "foveation/frame_stages.hpp"
#include "foveation/view_settings.hpp"
#include "foveation/view_tables.hpp"
#include "gpu/device_trace.hpp"
#include "gpu/eye.hpp"

namespace foveart::gpu {

struct DeviceFrame final : foveation::FrameResources {
  // Set by the caller, or by `begin`:
  Eye* eye = nullptr;
  const Tables* tables = nullptr;   // the view's tables on the device
  std::uint32_t slot = 0;           // the frame slot, < kFrameSlots
  VkImage image = VK_NULL_HANDLE;   // the swapchain image the encode copies into (null: none)
  bool srgb = true;                 // sRGB-encode (an sRGB swapchain format)
  foveation::DisplayTransform display;
  VkCommandBuffer cb = VK_NULL_HANDLE;  // null: `begin` gives it at the first stage that records
  std::function<VkCommandBuffer(DeviceFrame& frame, std::string* error)> begin;

  DeviceFrame* device() override { return this; }
  // The command buffer with the eye's frame begun in it (once per frame), or null with *error.
  VkCommandBuffer recording(const foveation::FrameContext& context, std::string* error);

  // What the stages so far have set (EyeFrame), and the colours uploaded.
  EyeFrame frame;
  std::size_t uploaded = 0;
  bool begun = false;
};

// The device's resources of a frame, or *error naming the stage that needs them.
DeviceFrame* device_frame(foveation::FrameResources& resources, const char* stage, std::string* error);

// The device's stage set for a view of `tables` with `settings`. `engine`
// set: stages 1-3 on the device through it; empty: through the engine's
// callback on the CPU, uploaded. `host_history` decides the history (null:
// make_temporal_history's, the one the CPU's set would keep).
foveation::FrameStages make_device_stages(std::shared_ptr<const foveation::ViewTables> tables,
                                          const foveation::ViewSettings& settings, DeviceTraceEngine engine,
                                          std::unique_ptr<foveation::TemporalHistory> host_history = nullptr);

}  // namespace foveart::gpu
