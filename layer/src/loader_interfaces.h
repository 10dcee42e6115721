/*
 * The OpenXR loader <-> API layer negotiation interface (loader interface
 * version 1). The 1.0.20 SDK headers Debian ships do not declare these
 * structs (later SDKs put them in openxr_loader_negotiation.h), so FoveaRT
 * declares them itself. The layout must match the loader's byte for byte:
 * field order and types follow the OpenXR loader specification, chapter
 * "Loader/API layer interface negotiation".
 */
#ifndef FOVEART_LAYER_LOADER_INTERFACES_H
#define FOVEART_LAYER_LOADER_INTERFACES_H

#include <stddef.h>
#include <stdint.h>

#include <openxr/openxr.h>

#ifdef __cplusplus
extern "C" {
#endif

#define FOVEART_LOADER_API_LAYER_INTERFACE_VERSION 1u
#define FOVEART_LOADER_INFO_STRUCT_VERSION 1u
#define FOVEART_API_LAYER_INFO_STRUCT_VERSION 1u
#define FOVEART_API_LAYER_NEXT_INFO_STRUCT_VERSION 1u
#define FOVEART_API_LAYER_CREATE_INFO_STRUCT_VERSION 1u
#define FOVEART_API_LAYER_MAX_SETTINGS_PATH_SIZE 512

typedef enum XrLoaderInterfaceStructs {
  XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,
  XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
  XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO = 4,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO = 5
} XrLoaderInterfaceStructs;

typedef struct XrApiLayerCreateInfo XrApiLayerCreateInfo;

typedef XrResult(XRAPI_PTR* PFN_xrCreateApiLayerInstance)(const XrInstanceCreateInfo* info,
                                                          const XrApiLayerCreateInfo* layerInfo,
                                                          XrInstance* instance);

/* What the loader supports; filled by the loader. */
typedef struct XrNegotiateLoaderInfo {
  XrLoaderInterfaceStructs structType; /* ..._LOADER_INFO */
  uint32_t structVersion;
  size_t structSize;
  uint32_t minInterfaceVersion;
  uint32_t maxInterfaceVersion;
  XrVersion minApiVersion;
  XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

/* What the layer answers; type/version/size filled by the loader. */
typedef struct XrNegotiateApiLayerRequest {
  XrLoaderInterfaceStructs structType; /* ..._API_LAYER_REQUEST */
  uint32_t structVersion;
  size_t structSize;
  uint32_t layerInterfaceVersion;
  XrVersion layerApiVersion;
  PFN_xrGetInstanceProcAddr getInstanceProcAddr;
  PFN_xrCreateApiLayerInstance createApiLayerInstance;
} XrNegotiateApiLayerRequest;

/* One link of the chain below this layer. */
typedef struct XrApiLayerNextInfo XrApiLayerNextInfo;
struct XrApiLayerNextInfo {
  XrLoaderInterfaceStructs structType; /* ..._API_LAYER_NEXT_INFO */
  uint32_t structVersion;
  size_t structSize;
  char layerName[XR_MAX_API_LAYER_NAME_SIZE];
  PFN_xrGetInstanceProcAddr nextGetInstanceProcAddr;
  PFN_xrCreateApiLayerInstance nextCreateApiLayerInstance;
  XrApiLayerNextInfo* next;
};

/* Passed to xrCreateApiLayerInstance. */
struct XrApiLayerCreateInfo {
  XrLoaderInterfaceStructs structType; /* ..._API_LAYER_CREATE_INFO */
  uint32_t structVersion;
  size_t structSize;
  void* loaderInstance;
  char settings_file_location[FOVEART_API_LAYER_MAX_SETTINGS_PATH_SIZE];
  XrApiLayerNextInfo* nextInfo;
};

typedef XrResult(XRAPI_PTR* PFN_xrNegotiateLoaderApiLayerInterface)(
    const XrNegotiateLoaderInfo* loaderInfo, const char* apiLayerName,
    XrNegotiateApiLayerRequest* apiLayerRequest);

#ifdef __cplusplus
} /* extern "C" */
#endif

#ifdef __cplusplus
/* Layout checks against the loader's ABI on LP64. */
static_assert(sizeof(XrNegotiateLoaderInfo) == 40, "loader ABI");
static_assert(offsetof(XrNegotiateApiLayerRequest, getInstanceProcAddr) == 32, "loader ABI");
static_assert(offsetof(XrApiLayerNextInfo, nextGetInstanceProcAddr) == 16 + XR_MAX_API_LAYER_NAME_SIZE,
              "loader ABI");
static_assert(offsetof(XrApiLayerCreateInfo, nextInfo) == 24 + FOVEART_API_LAYER_MAX_SETTINGS_PATH_SIZE,
              "loader ABI");
#endif

#endif /* FOVEART_LAYER_LOADER_INTERFACES_H */
