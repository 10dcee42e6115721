#include "device_trace_engine.hpp"

#include <cstddef>

#include "gpu/shader_interface/device_trace.h"

#include "gpu/device_trace.hpp"

namespace foveart::layer {

// The count buffer the engine reads is the gpu module's control words 0-7.
static_assert(sizeof(XrFoveatedDeviceRayCountFOVEART) == FOVEART_DEVICE_RAY_COUNT_WORDS * 4);
static_assert(offsetof(XrFoveatedDeviceRayCountFOVEART, dispatch64) == 4 && offsetof(XrFoveatedDeviceRayCountFOVEART, traceRays) == 16);

namespace {

XrFoveatedDeviceBufferFOVEART xr_buffer(const gpu::BufferRange& range) {
  return {range.buffer, range.offset, range.size};
}

}  // namespace

XrFoveatedDeviceRayBatchFOVEART xr_device_ray_batch(const gpu::DeviceRayBatch& batch) {
  XrFoveatedDeviceRayBatchFOVEART xr{};
  xr.type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
  xr.frameIndex = batch.frame_index;
  xr.view = batch.view;
  xr.rayCapacity = batch.ray_capacity;
  xr.raysPerPoint = batch.rays_per_point;
  xr.rayCount = xr_buffer(batch.ray_count);
  xr.rays = xr_buffer(batch.rays);
  xr.pointIndex = xr_buffer(batch.point_index);
  xr.colors = xr_buffer(batch.colors);
  xr.commandBuffer = batch.command_buffer;
  return xr;
}

gpu::DeviceTraceEngine xr_device_trace_engine(PFN_xrFoveatedTraceRaysDeviceFOVEART trace, void* user_data,
                                              XrResult* result) {
  *result = XR_SUCCESS;
  return [trace, user_data, result](const gpu::DeviceRayBatch& batch) {
    const XrFoveatedDeviceRayBatchFOVEART xr = xr_device_ray_batch(batch);
    *result = trace(user_data, &xr);
    return XR_SUCCEEDED(*result);
  };
}

}  // namespace foveart::layer
