// The few entry points of the public FOVE SDK C API (FoveAPI.h, v1.x) that the FOVE
// backend uses, declared here so that nothing depends on the SDK at build time. The
// library is loaded with dlopen() and these are resolved with dlsym(). Values and
// layouts follow the public header; the tests' fake client library implements the
// same declarations (tests/gaze_provider/fake_fove/).
#pragma once

#include <cstdint>

extern "C" {

typedef struct Fove_Headset_ Fove_Headset;  // opaque

typedef enum {
  Fove_ErrorCode_None = 0,
  Fove_ErrorCode_Connect_NotConnected = 7,
  Fove_ErrorCode_API_InvalidArgument = 103,
  Fove_ErrorCode_API_NotRegistered = 104,
  Fove_ErrorCode_API_Timeout = 130,
  Fove_ErrorCode_Data_Unreadable = 1002,
  Fove_ErrorCode_Data_NoUpdate = 1003,
  Fove_ErrorCode_Data_Uncalibrated = 1004,
  Fove_ErrorCode_Data_Unreliable = 1006,
  Fove_ErrorCode_Data_LowAccuracy = 1007,
  Fove_ErrorCode_Hardware_Disconnected = 2006,
  Fove_ErrorCode_UnknownError = 9000,
  Fove_ErrorCode_Force32 = 0x7fffffff,  // keep the enum int-sized, as in the SDK
} Fove_ErrorCode;

typedef enum {
  Fove_ClientCapabilities_None = 0,
  Fove_ClientCapabilities_EyeTracking = 1 << 3,
  Fove_ClientCapabilities_Force32 = 0x7fffffff,
} Fove_ClientCapabilities;

typedef enum { Fove_Eye_Left = 0, Fove_Eye_Right = 1, Fove_Eye_Force32 = 0x7fffffff } Fove_Eye;

typedef enum {
  Fove_EyeState_NotDetected = 0,
  Fove_EyeState_Opened = 1,
  Fove_EyeState_Closed = 2,
  Fove_EyeState_Force32 = 0x7fffffff,
} Fove_EyeState;

typedef struct {
  float x, y, z;
} Fove_Vec3;

typedef struct {
  Fove_Vec3 origin;
  Fove_Vec3 direction;
} Fove_Ray;

typedef struct {
  uint64_t id;         // incremental frame counter
  uint64_t timestamp;  // capture time, microseconds since an unspecified epoch
} Fove_FrameTimestamp;

typedef Fove_ErrorCode (*PFN_fove_createHeadset)(Fove_ClientCapabilities, Fove_Headset**);
typedef Fove_ErrorCode (*PFN_fove_Headset_destroy)(Fove_Headset*);
typedef Fove_ErrorCode (*PFN_fove_Headset_waitForProcessedEyeFrame)(Fove_Headset*);
typedef Fove_ErrorCode (*PFN_fove_Headset_fetchEyeTrackingData)(Fove_Headset*, Fove_FrameTimestamp*);
typedef Fove_ErrorCode (*PFN_fove_Headset_getGazeVector)(Fove_Headset*, Fove_Eye, Fove_Vec3*);
typedef Fove_ErrorCode (*PFN_fove_Headset_getCombinedGazeRay)(Fove_Headset*, Fove_Ray*);
typedef Fove_ErrorCode (*PFN_fove_Headset_getEyeState)(Fove_Headset*, Fove_Eye, Fove_EyeState*);
typedef Fove_ErrorCode (*PFN_fove_Headset_isHardwareConnected)(Fove_Headset*, bool*);

}  // extern "C"
