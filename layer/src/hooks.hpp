// The functions the layer intercepts. Everything else is the next link's.
#pragma once

#include <string_view>

#include "loader_interfaces.h"
#include "state.hpp"

namespace foveart::layer {

// Our hook for `name`, or null to pass through. Extension functions are found
// only when the instance enabled XR_FOVEART_foveated_ray_tracing.
PFN_xrVoidFunction find_hook(std::string_view name, const InstanceState& instance);
bool is_extension_function(std::string_view name);

XrResult negotiate(const XrNegotiateLoaderInfo* loader_info, const char* layer_name,
                   XrNegotiateApiLayerRequest* request);

}  // namespace foveart::layer
