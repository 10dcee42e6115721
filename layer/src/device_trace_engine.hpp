// The app's device trace (XrFoveatedDeviceTraceInfoFOVEART) as the gpu
// module's DeviceTraceEngine: each gpu::DeviceRayBatch handed on as an
// XrFoveatedDeviceRayBatchFOVEART, the engine's XrResult kept for the stats.
#pragma once

#include <openxr/openxr.h>

#include "gpu/device_trace.hpp"
#include "layer/XR_FOVEART_foveated_ray_tracing.h"

namespace foveart::layer {

// The batch as the extension hands it to the engine, its footprint and
// addresses chained in its `next` (pointing into this object: not copyable).
struct XrDeviceRayBatch {
  XrFoveatedDeviceRayBatchFOVEART batch{};
  XrFoveatedDeviceRayFootprintFOVEART footprint{};
  XrFoveatedDeviceRayAddressesFOVEART addresses{};
  explicit XrDeviceRayBatch(const gpu::DeviceRayBatch& device_batch);
  XrDeviceRayBatch(const XrDeviceRayBatch&) = delete;
  XrDeviceRayBatch& operator=(const XrDeviceRayBatch&) = delete;
};

// Calls `trace` with each batch; *result (which outlives the engine) holds
// the last call's result, XR_SUCCESS until it is called.
gpu::DeviceTraceEngine xr_device_trace_engine(PFN_xrFoveatedTraceRaysDeviceFOVEART trace, void* user_data,
                                              XrResult* result);

}  // namespace foveart::layer
