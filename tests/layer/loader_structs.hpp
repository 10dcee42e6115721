// What a conforming OpenXR 1.0 loader passes to xrNegotiateLoaderApiLayerInterface,
// for tests that call the layer's negotiation entry point themselves.
#pragma once

#include "loader_interfaces.h"

namespace foveart::layer::test {

inline XrNegotiateLoaderInfo conforming_loader_info() {
  XrNegotiateLoaderInfo info{};
  info.structType = XR_LOADER_INTERFACE_STRUCT_LOADER_INFO;
  info.structVersion = FOVEART_LOADER_INFO_STRUCT_VERSION;
  info.structSize = sizeof(info);
  info.minInterfaceVersion = 1;
  info.maxInterfaceVersion = 1;
  info.minApiVersion = XR_MAKE_VERSION(1, 0, 0);
  info.maxApiVersion = XR_MAKE_VERSION(1, 0x3ff, 0xfff);
  return info;
}

inline XrNegotiateApiLayerRequest empty_api_layer_request() {
  XrNegotiateApiLayerRequest request{};
  request.structType = XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST;
  request.structVersion = FOVEART_API_LAYER_INFO_STRUCT_VERSION;
  request.structSize = sizeof(request);
  return request;
}

}  // namespace foveart::layer::test
