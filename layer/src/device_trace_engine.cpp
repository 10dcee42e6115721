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

XrDeviceRayBatch::XrDeviceRayBatch(const gpu::DeviceRayBatch& in) {
  XrFoveatedDeviceRayBatchFOVEART& xr = batch;
  xr.type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
  xr.next = &footprint;
  xr.frameIndex = in.frame_index;
  xr.view = in.view;
  xr.rayCapacity = in.ray_capacity;
  xr.raysPerPoint = in.rays_per_point;
  xr.rayCount = xr_buffer(in.ray_count);
  xr.rays = xr_buffer(in.rays);
  xr.pointIndex = xr_buffer(in.point_index);
  xr.colors = xr_buffer(in.colors);
  xr.commandBuffer = in.command_buffer;
  footprint.type = XR_TYPE_FOVEATED_DEVICE_RAY_FOOTPRINT_FOVEART;
  footprint.next = &addresses;
  footprint.footprints = xr_buffer(in.footprints);
  addresses.type = XR_TYPE_FOVEATED_DEVICE_RAY_ADDRESSES_FOVEART;
  addresses.rayCount = in.addresses.ray_count;
  addresses.rays = in.addresses.rays;
  addresses.pointIndex = in.addresses.point_index;
  addresses.colors = in.addresses.colors;
  addresses.footprints = in.addresses.footprints;
}

gpu::DeviceTraceEngine xr_device_trace_engine(PFN_xrFoveatedTraceRaysDeviceFOVEART trace, void* user_data,
                                              XrResult* result) {
  *result = XR_SUCCESS;
  return [trace, user_data, result](const gpu::DeviceRayBatch& batch) {
    const XrDeviceRayBatch xr(batch);
    *result = trace(user_data, &xr.batch);
    return XR_SUCCEEDED(*result);
  };
}

}  // namespace foveart::layer
