/*
 * XR_FOVEART_foveated_ray_tracing — foveated ray tracing for any OpenXR engine.
 *
 * Provided by the API layer XR_APILAYER_FOVEART_foveated_ray_tracing
 * (libXrApiLayer_foveart.so). Enable the layer (manifest) and this extension
 * (XrInstanceCreateInfo::enabledExtensionNames); then fetch the functions below
 * with xrGetInstanceProcAddr. Without the extension enabled they are not
 * returned (XR_ERROR_FUNCTION_UNSUPPORTED) and the layer is transparent.
 *
 * Usage:
 *   1. xrCreateSession with XrGraphicsBindingVulkan2KHR (XR_KHR_vulkan_enable2).
 *   2. xrCreateFoveatedRendererFOVEART(session, &info, &renderer) with the
 *      engine's ray-trace callback (foveation/ray_trace.h) and its user data.
 *      Each other field either names a value or leaves it to the layer's
 *      config file (see "Defaults" below).
 *   3. Each frame, chain an XrFoveatedRayTracingLayerFOVEART into the `next`
 *      chain of the XrCompositionLayerProjection to be ray traced. The layer
 *      traces both views at xrEndFrame, writes them into swapchains it owns and
 *      replaces the views' subImage before the runtime sees the frame. The
 *      app's own images for those views are not shown (it may submit a cheap
 *      placeholder; it is used as the fallback, see below). Other composition
 *      layers pass through untouched.
 *   4. xrGetFoveatedRendererStatsFOVEART at any time; xrDestroyFoveatedRendererFOVEART
 *      before xrDestroySession (xrDestroySession also destroys it).
 *
 * Threads:  the callback runs on the layer's worker threads during xrEndFrame,
 *           several batches at once. The create/destroy/stats functions are
 *           thread-safe.
 * Fallback: no or invalid gaze -> fixed foveation at the lens centre. If a
 *           frame cannot be produced (callback error, NaN/Inf colours, upload
 *           failure) the view is forwarded with the app's own subImage (a
 *           device trace's colours are judged on the device: see "Errors"
 *           there); the first failure of each kind is logged and every one is
 *           counted in the stats. No garbage frame is ever shown.
 * Defaults: every field of XrFoveatedRendererCreateInfoFOVEART other than
 *           traceRays/userData can take the layer config's value instead of
 *           the app's ("k", "density_scale", ... in the config; docs/layer.md):
 *             k, densityScale, raysPerPoint   0
 *             gazeProviderSpec                NULL or ""
 *             interpolation                   XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART
 *             temporal                        XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART
 *             gazeSource                      XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART
 *           Zero is a real choice for the three enums (nearest neighbour, no
 *           temporal history, fixed foveation): to leave everything to the
 *           config, set all six fields as in the table.
 * Numbers:  structure type values are in the range 1000900000+ which the
 *           OpenXR registry has not assigned; this is a private (vendor)
 *           extension.
 * Versions: 11 adds XR_FOVEATED_FALLBACK_INVALID_VIEW_BIT_FOVEART: a view whose
 *           pose or field of view cannot be traced is forwarded untraced;
 *           nothing else changed.
 *           10 adds the per-stage cost of content density
 *           (XrFoveatedRendererDensityStatsFOVEART, chained into the stats);
 *           nothing else changed.
 *           9 adds the app-recorded trace (XrFoveatedAppTraceInfoFOVEART,
 *           xrAcquireFoveatedRayBatchFOVEART, xrReleaseFoveatedRayBatchFOVEART);
 *           nothing else changed.
 *           8 adds each device ray's footprint (XrFoveatedDeviceRayFootprintFOVEART)
 *           and the device trace buffers' device addresses
 *           (XrFoveatedDeviceRayAddressesFOVEART), both chained into the
 *           batch's `next`, and makes traceRays rows (see "Rays"); no layout
 *           changed.
 *           7 makes the device trace's indirect dispatch two-dimensional
 *           (dispatch64: x <= 65535 workgroups by y rows, see "Rays"; one row
 *           as before up to 65535 * 64 rays), renames FoveartDeviceRayCount
 *           XrFoveatedDeviceRayCountFOVEART (the old name stays, deprecated)
 *           and states the barriers as recorded; no layout changed.
 *           6 pipelines the device trace's frames: up to two in flight,
 *           its handles valid until their frame slot's submission finished,
 *           faults judged on the device and counted frames later (see the
 *           device trace's "Lifetime" and "Errors"); no struct changed. 5 renames five stats fields for the one temporal name, at the same
 *           offsets and types (interpolateMs -> reconstructMs, taaMs ->
 *           temporalMs, gpuTaaMs -> gpuTemporalMs, taaResetLastFrame ->
 *           temporalResetLastFrame, taaResets -> temporalResets): binaries built
 *           against 4 read the same values. 4 added the device trace. The
 *           manifests advertise the version defined here.
 */
#ifndef XR_FOVEART_FOVEATED_RAY_TRACING_H
#define XR_FOVEART_FOVEATED_RAY_TRACING_H

#include <openxr/openxr.h>

#include "foveation/ray_trace.h"

#ifdef __cplusplus
extern "C" {
#endif

#define XR_FOVEART_foveated_ray_tracing 1
#define XR_FOVEART_foveated_ray_tracing_SPEC_VERSION 11
#define XR_FOVEART_FOVEATED_RAY_TRACING_EXTENSION_NAME "XR_FOVEART_foveated_ray_tracing"
#define XR_FOVEART_API_LAYER_NAME "XR_APILAYER_FOVEART_foveated_ray_tracing"

XR_DEFINE_HANDLE(XrFoveatedRendererFOVEART)

#ifdef __cplusplus
#define XR_FOVEART_STRUCTURE_TYPE(value) static_cast<XrStructureType>(value)
#else
#define XR_FOVEART_STRUCTURE_TYPE(value) ((XrStructureType)(value))
#endif
#define XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900000)
#define XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900001)
#define XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900002)
#define XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900003)
#define XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900004)
#define XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900005)
#define XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900012)

typedef enum XrFoveatedInterpolationFOVEART {
  XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART = 0, /* nearest neighbour */
  XR_FOVEATED_INTERPOLATION_MSM_FOVEART = 1,     /* modified Shepard method, MSM (thesis 4.3) */
  XR_FOVEATED_INTERPOLATION_RBF_FOVEART = 2,     /* radial basis functions + constant term */
  /* the config's "interpolation" */
  XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART = 0x7FFFFFFE,
  XR_FOVEATED_INTERPOLATION_MAX_ENUM_FOVEART = 0x7FFFFFFF
} XrFoveatedInterpolationFOVEART;

typedef enum XrFoveatedGazeSourceFOVEART {
  XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART = 0,     /* fixed foveation at the lens centre */
  XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART = 1, /* FoveaRT gaze provider (gazeProviderSpec) */
  XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART = 2, /* runtime's XR_EXT_eye_gaze_interaction */
  /* the config's "gaze_source"; create info only, never in the stats */
  XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART = 0x7FFFFFFE,
  XR_FOVEATED_GAZE_SOURCE_MAX_ENUM_FOVEART = 0x7FFFFFFF
} XrFoveatedGazeSourceFOVEART;

/* What a frame keeps from earlier frames (the config's "temporal"; docs/layer.md). */
typedef enum XrFoveatedTemporalFOVEART {
  XR_FOVEATED_TEMPORAL_OFF_FOVEART = 0,   /* each frame from its own rays */
  XR_FOVEATED_TEMPORAL_IMAGE_FOVEART = 1, /* an image history, reprojected with the head and blended */
  XR_FOVEATED_TEMPORAL_RAYS_FOVEART = 2,  /* a render cache of the traced rays, blended alike */
  /* the config's "temporal"; create info only, never in the stats */
  XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART = 0x7FFFFFFE,
  XR_FOVEATED_TEMPORAL_MAX_ENUM_FOVEART = 0x7FFFFFFF
} XrFoveatedTemporalFOVEART;

/* Fallback state bits (XrFoveatedRendererStatsFOVEART::fallbackFlags). */
typedef XrFlags64 XrFoveatedFallbackFlagsFOVEART;
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART = 0x00000001;
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART = 0x00000002;
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART = 0x00000004;
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART = 0x00000008;
/* The point set / neighbour tables are still being built or loaded. */
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART = 0x00000010;
/* The frame path is not available (no Vulkan session, build without foveation). */
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART = 0x00000020;
/* Building the tables for this view size failed (logged): it falls back for good. */
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_TABLES_FAILED_BIT_FOVEART = 0x00000040;
/* The view's imageRect lies outside its swapchain image: forwarded as the app sent
 * it, for the runtime to judge, and not ray traced. */
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_INVALID_IMAGE_RECT_BIT_FOVEART = 0x00000080;
/* The view cannot be traced: a position that is not finite or lies beyond 1e9 m, an
 * orientation that is not a unit quaternion, or a field of view that is not finite, inside
 * (-pi/2, pi/2) and ordered. Forwarded as the app sent it, for the runtime to judge, and not
 * ray traced; at xrAcquireFoveatedRayBatchFOVEART, that view gets no rays. */
static const XrFoveatedFallbackFlagsFOVEART XR_FOVEATED_FALLBACK_INVALID_VIEW_BIT_FOVEART = 0x00000100;

typedef struct XrFoveatedRendererCreateInfoFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RENDERER_CREATE_INFO_FOVEART */
  const void* XR_MAY_ALIAS next;
  FoveartTraceRaysFn traceRays; /* required unless a device or app-recorded trace is chained (below) */
  void* userData;               /* passed back to traceRays unchanged */
  XrFoveatedInterpolationFOVEART interpolation; /* ..._USE_CONFIG_FOVEART = config (0 is NEAREST) */
  uint32_t k;           /* neighbours per pixel (1 for nearest), 1..20; 0 = config */
  float densityScale;   /* point density scale (thesis "scale"), (0, 16]; 0 = config */
  uint32_t raysPerPoint; /* jittered rays per point, 1..64 (thesis: 32); 0 = config */
  XrFoveatedTemporalFOVEART temporal; /* ..._USE_CONFIG_FOVEART = config (0 is OFF) */
  XrFoveatedGazeSourceFOVEART gazeSource; /* ..._USE_CONFIG_FOVEART = config (0 is NONE) */
  const char* gazeProviderSpec; /* for ..._PROVIDER: "sim", "replay:FILE", ...; NULL or "" = config */
} XrFoveatedRendererCreateInfoFOVEART;

/* The curve that maps radiance to display values after the exposure (the config's "tone_map"). */
typedef enum XrFoveatedToneMapFOVEART {
  XR_FOVEATED_TONE_MAP_NONE_FOVEART = 0,        /* clamp to [0, 1] */
  XR_FOVEATED_TONE_MAP_PBR_NEUTRAL_FOVEART = 1, /* Khronos PBR Neutral */
  XR_FOVEATED_TONE_MAP_ACES_FOVEART = 2,        /* ACES filmic (Narkowicz's fit) */
  XR_FOVEATED_TONE_MAP_USE_CONFIG_FOVEART = 0x7FFFFFFE,
  XR_FOVEATED_TONE_MAP_MAX_ENUM_FOVEART = 0x7FFFFFFF
} XrFoveatedToneMapFOVEART;

/* Optional, per frame: chain into XrFoveatedRayTracingLayerFOVEART::next to set
 * how this frame's radiance becomes display values (an engine's auto exposure
 * changes it from frame to frame). Without it, or for a field that says "use
 * the config", the config's "exposure" and "tone_map" apply. The transform runs
 * after reconstruction and temporal history, before the sRGB encode, on
 * either path; the callback's colours and the history stay radiance.
 * An invalid value (exposure not finite or <= 0, an unknown curve) is logged
 * once and the config's value used instead. */
typedef struct XrFoveatedDisplayTransformFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_DISPLAY_TRANSFORM_FOVEART */
  const void* XR_MAY_ALIAS next;
  float exposure;       /* linear scale of radiance before the curve, > 0; 0 = config */
  XrFoveatedToneMapFOVEART toneMap; /* ..._USE_CONFIG_FOVEART = config (0 is NONE) */
} XrFoveatedDisplayTransformFOVEART;

/* Chain into XrCompositionLayerProjection::next to have its views ray traced. */
typedef struct XrFoveatedRayTracingLayerFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RAY_TRACING_LAYER_FOVEART */
  const void* XR_MAY_ALIAS next;
  XrFoveatedRendererFOVEART renderer;
} XrFoveatedRayTracingLayerFOVEART;

/* Index 0 = left eye, 1 = right eye; times of the last frame, in milliseconds. */
typedef struct XrFoveatedRendererStatsFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART */
  void* XR_MAY_ALIAS next;
  uint64_t framesTraced;     /* frames with at least one view traced */
  uint64_t framesFallback;   /* views forwarded with the app's own image */
  uint32_t pointsPerEye[2];  /* visible points */
  uint32_t raysPerEye[2];
  float selectMs[2];
  float traceMs[2];
  float reconstructMs[2];
  float temporalMs[2];
  float uploadMs[2];
  float gazeAgeMs;           /* age of the newest gaze sample at composition (xrEndFrame), before prediction */
  XrFoveatedGazeSourceFOVEART gazeSource; /* source actually used last frame */
  XrFoveatedFallbackFlagsFOVEART fallbackFlags; /* state of the last frame */
  uint64_t callbackFailures; /* batches the callback failed (error code) */
  uint64_t invalidColours;   /* rays returning NaN/Inf/negative colour */
  uint64_t gazeLostFrames;   /* frames with fixed foveation for lack of gaze */
  XrVector2f gazePixel[2];   /* foveation centre per eye last frame, pixels of the view's imageRect */
} XrFoveatedRendererStatsFOVEART;

/* Chain into XrFoveatedRendererStatsFOVEART::next to also get what the layer
 * refused or worked around since the renderer was created. Each is logged once with its reason. */
typedef struct XrFoveatedRendererInputStatsFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART */
  void* XR_MAY_ALIAS next;
  uint64_t cacheFilesRejected;    /* table cache files rejected (corrupt, other version or parameters): rebuilt */
  uint64_t cacheFailures;         /* cache files not written, or the cache directory refused (tables then not cached) */
  uint64_t tableBuildsFailed;     /* view sizes whose tables could not be built: those views fall back */
  uint64_t tableSetsEvicted;      /* table sets dropped, least recently used first, to bound memory */
  uint32_t tableSetsResident;     /* table sets held now (built or building) */
  uint32_t reserved;
  uint64_t gazeBehindViews;       /* eye-frames whose valid gaze pointed backwards: foveated at the lens centre */
  uint64_t invalidImageRectViews; /* views whose imageRect lies outside the swapchain: forwarded, not traced */
  uint64_t foreignSessionLayers;  /* projection layers naming this renderer in another session's xrEndFrame: forwarded */
} XrFoveatedRendererInputStatsFOVEART;

/* Where a renderer reconstructed its last frame (the config's "reconstruction"). */
typedef enum XrFoveatedReconstructionPathFOVEART {
  XR_FOVEATED_RECONSTRUCTION_PATH_NONE_FOVEART = 0, /* no frame reconstructed yet */
  XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART = 1,  /* foveation's CPU gather, temporal history and encode, then an upload */
  XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART = 2,  /* Vulkan compute on the app's device (shaders/) */
  XR_FOVEATED_RECONSTRUCTION_PATH_MAX_ENUM_FOVEART = 0x7FFFFFFF
} XrFoveatedReconstructionPathFOVEART;

/* Chain into XrFoveatedRendererStatsFOVEART::next to also get the reconstruction path
 * of the last frame and, on the GPU path, each stage's GPU time per eye from timestamps (0 on the CPU
 * path): scatter of the traced colours, gather, temporal history, and sRGB encode with the copy into
 * the image. With a device trace, the device's rays, the engine's trace and the resolve are the
 * stats' traceMs, their own slot, and the scatter has nothing to do. The GPU path's frames are
 * in flight when xrEndFrame returns: its stage times (and those stats' traceMs, reconstructMs,
 * temporalMs, and a device trace's pointsPerEye and raysPerEye) describe the newest frame whose
 * submission has finished, up to two frames older than the last xrEndFrame; a device trace's
 * invalidColours and framesFallback are counted then too. */
typedef struct XrFoveatedRendererReconstructionStatsFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART */
  void* XR_MAY_ALIAS next;
  XrFoveatedReconstructionPathFOVEART path;
  XrFoveatedTemporalFOVEART temporal; /* the temporal mode of the last frame (the path's default when the config leaves it) */
  uint32_t gpuFallbacks; /* views the GPU path could not do (logged once): reconstructed on the CPU instead */
  float gpuScatterMs[2];
  float gpuGatherMs[2];
  float gpuTemporalMs[2];
  float gpuEncodeMs[2];
  XrBool32 temporalResetLastFrame[2]; /* the temporal history restarted in the last frame (a saccade's or blink's onset, a gaze jump, new size) */
  uint64_t temporalResets;            /* history restarts since the renderer was created, both eyes */
  XrBool32 gazeSaccadeLastFrame; /* the gaze provider flagged a saccade for the last frame */
  XrBool32 gazeBlinkLastFrame;   /* ... or a blink (held gaze) */
} XrFoveatedRendererReconstructionStatsFOVEART;

/* Chain into XrFoveatedRendererStatsFOVEART::next to also get what choosing the
 * point density by content ("content_contrast" / "content_rays" in the config)
 * cost per eye, in milliseconds, and the points it thinned. All 0 while it is off.
 * The stages (docs/content_density.md):
 *   CPU trace (the traceRays callback, either reconstruction path), host time of
 *   the last frame: levelsMs, the tiles' levels from the last frame's luminance
 *   ranges; testMs, the per-point test (thinned or traced, rays by the tile's
 *   contrast); observeMs, the traced colours into their tiles' ranges; fillMs,
 *   the thinned points from their parents. Test and observe run inside the
 *   parallel trace pass: their time summed over the threads, divided by the
 *   threads. They are part of the stats' selectMs and traceMs. gpu* are 0.
 *   Device trace (XrFoveatedDeviceTraceInfoFOVEART, or the app-recorded trace
 *   XrFoveatedAppTraceInfoFOVEART), GPU time from timestamps,
 *   part of the stats' traceMs: gpuFillMs, the thinned points from their
 *   parents; gpuContrastMs, the tiles' contrast for the next frame. Like the
 *   other GPU stage times (and pointsThinned with them) they describe the newest
 *   frame whose submission finished, up to two frames older than the last
 *   xrEndFrame. The host stages are 0. */
typedef struct XrFoveatedRendererDensityStatsFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART */
  void* XR_MAY_ALIAS next;
  uint32_t pointsThinned[2]; /* visible points left untraced in flat tiles, filled from their parents */
  float levelsMs[2];
  float testMs[2];
  float observeMs[2];
  float fillMs[2];
  float gpuFillMs[2];
  float gpuContrastMs[2];
} XrFoveatedRendererDensityStatsFOVEART;

#ifdef XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>

/*
 * The device trace: for an engine that traces on the GPU. Chain an
 * XrFoveatedDeviceTraceInfoFOVEART into XrFoveatedRendererCreateInfoFOVEART::next;
 * traceRays may then be NULL. With it, no ray, colour or image crosses to the
 * host in a frame: the layer selects the visible points and makes their rays
 * on the device (from the gaze and the view, pushed as constants), hands the
 * engine device buffers and a command buffer to record its trace into, and
 * reconstructs from the colours the engine writes.
 *
 * Threads:  traceRaysDevice runs on the thread that called xrEndFrame, once
 *           per traced view, one view after the other, both into the frame's
 *           one command buffer. It records; it must not submit, end or reset
 *           the command buffer, nor wait on the queue.
 * Queue:    the command buffer belongs to the queue family and queue of the
 *           session's XrGraphicsBindingVulkan2KHR and is submitted there
 *           inside xrEndFrame. Every buffer below is the layer's, created with
 *           VK_SHARING_MODE_EXCLUSIVE on that family (no ownership transfer)
 *           and usage STORAGE_BUFFER | TRANSFER_SRC, plus INDIRECT_BUFFER for
 *           rayCount and TRANSFER_DST for colors.
 * Barriers: the layer records one vkCmdPipelineBarrier with one
 *           VkMemoryBarrier (no buffer or image barriers, no dependency
 *           flags) on each side of the call. Before it: srcStageMask
 *           COMPUTE_SHADER | TRANSFER, srcAccessMask SHADER_WRITE |
 *           TRANSFER_WRITE (the layer's ray shader and its fills of the counts
 *           and colours), dstStageMask ALL_COMMANDS, dstAccessMask
 *           MEMORY_READ | MEMORY_WRITE: the engine may read the rays and
 *           counts and write the colours in any stage (shaders, copies,
 *           indirect commands). After it: srcStageMask ALL_COMMANDS,
 *           srcAccessMask MEMORY_WRITE, dstStageMask COMPUTE_SHADER |
 *           DRAW_INDIRECT, dstAccessMask SHADER_READ | INDIRECT_COMMAND_READ:
 *           the engine's writes in any stage are visible to the layer's
 *           compute shaders and indirect dispatches that follow. Between its
 *           own commands the engine synchronises as it would anywhere.
 * State:    the command buffer is outside any render pass; the engine may
 *           bind pipelines, descriptor sets and push constants of its own
 *           (the layer rebinds what it needs afterwards).
 * Lifetime: up to XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS (2) frames are in
 *           flight: xrEndFrame submits a frame and returns without waiting
 *           for it. A call's handles belong to frame slot frameIndex %
 *           XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS and stay valid until that
 *           slot's submission finished; when a call of that slot comes again,
 *           the slot's previous submission has finished, so the engine may
 *           keep resources of its own per slot (a descriptor set, a buffer it
 *           writes) indexed the same way and reuse them then. Within a slot
 *           the handles may still change from one call to the next (a view
 *           size changes): update descriptors from every batch, or cache them
 *           by handle. (Before version 6 each call's submission had finished
 *           before the next call; an engine written for that and keeping
 *           nothing of its own across calls works unchanged.)
 * Rays:     rays[0, count) of the frame are valid, count in the rayCount
 *           buffer (XrFoveatedDeviceRayCountFOVEART) written on the device: dispatch
 *           indirectly from it. dispatch64 is two-dimensional, x <= 65535
 *           workgroups by y rows, so a compute shader of 64 invocations
 *           traces ray (gl_WorkGroupID.y * gl_NumWorkGroups.x +
 *           gl_WorkGroupID.x) * 64 + gl_LocalInvocationIndex and returns when
 *           that is >= count (y is 1 up to 65535 * 64 rays). traceRays
 *           (vkCmdTraceRaysIndirectKHR, from the rayCount buffer's device
 *           address) is width x height x 1, rows of at most 65536, at most
 *           2^30 launches in all (Vulkan's minimum limits): launch (x, y)
 *           traces ray y * width + x, and that plus width * height while it
 *           is < count (only past 2^30 rays). Each ray is 32 bytes (std430
 *           `vec4 origin_sample_x; vec4 direction_sample_y;`): origin in
 *           metres, unit direction, tracking space; the screen position in
 *           pixels, as in FoveartRayBatch. pointIndex holds the point of each
 *           ray; rays of one point are consecutive, raysPerPoint of them
 *           (with content density, "content_contrast" or "content_rays" in
 *           the layer's config, from 1 to raysPerPoint, and fewer points).
 * Colours:  per ray a vec4: linear radiance in rgb (finite, >= 0) and in w the
 *           distance in metres to the nearest hit (+inf: a miss; NaN: none
 *           given, rotation-only reprojection). The layer fills the buffer
 *           with NaN before the call: a ray left unwritten is an invalid colour.
 * Errors:   return XR_SUCCESS, or an error code: the view then shows the
 *           app's own image this frame, counted at once (callbackFailures).
 *           What the engine recorded before it returned is still submitted
 *           (both views share the frame's submission): leave the command
 *           buffer fit to submit. NaN, infinite or negative colours, or rays
 *           left unwritten, are found on the device, which then keeps the
 *           view's last good image for that frame (the app's own while the
 *           layer has seen no good frame of the view yet: it waits for those
 *           frames) and the temporal history as it was; the layer reads the
 *           fault when the frame's slot comes round, counts it (invalidColours,
 *           framesFallback) and restarts the view's history. Never throw
 *           across this call.
 * Both:     with traceRays and traceRaysDevice the device trace is used where
 *           the layer reconstructs on the GPU, traceRays elsewhere (CPU
 *           reconstruction, a device the shaders cannot run on).
 * Growth:   both structs follow OpenXR: (type, next). No struct here
 *           changes size or layout; what is added comes as a new structure
 *           type chained in `next` (OpenXR's rule). The layer ignores
 *           chained structures whose type it does not know; an engine
 *           ignores those in a batch's `next` likewise.
 */
#define XR_TYPE_FOVEATED_DEVICE_TRACE_INFO_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900006)
/* Frames of the device trace in flight at once; a call's slot is frameIndex % this. */
#define XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS 2
#define XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900007)

/* The rayCount buffer's contents, written on the device before the call. */
typedef struct XrFoveatedDeviceRayCountFOVEART {
  uint32_t count;            /* valid rays */
  uint32_t dispatch64[3];    /* VkDispatchIndirectCommand for 64 rays per workgroup: x <= 65535 by y rows, 1 */
  uint32_t traceRays[3];     /* VkTraceRaysIndirectCommandKHR: width x height x 1 (see "Rays") */
  uint32_t reserved;
} XrFoveatedDeviceRayCountFOVEART;
/* Deprecated: the name before version 7, kept for old sources; use XrFoveatedDeviceRayCountFOVEART. */
typedef XrFoveatedDeviceRayCountFOVEART FoveartDeviceRayCount;

/* A range of one of the layer's buffers. */
typedef struct XrFoveatedDeviceBufferFOVEART {
  VkBuffer buffer;
  VkDeviceSize offset; /* a multiple of minStorageBufferOffsetAlignment */
  VkDeviceSize size;   /* bytes */
} XrFoveatedDeviceBufferFOVEART;

/* One view's trace on the device. */
typedef struct XrFoveatedDeviceRayBatchFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART */
  const void* XR_MAY_ALIAS next;
  uint64_t frameIndex;
  const FoveartEyeView* view;  /* as in FoveartRayBatch */
  uint32_t rayCapacity;        /* rays the buffers hold; count <= rayCapacity */
  uint32_t raysPerPoint;
  XrFoveatedDeviceBufferFOVEART rayCount;   /* XrFoveatedDeviceRayCountFOVEART; read (and indirect) only */
  XrFoveatedDeviceBufferFOVEART rays;       /* rayCapacity x 32 bytes; read only */
  XrFoveatedDeviceBufferFOVEART pointIndex; /* rayCapacity x uint32_t; read only */
  XrFoveatedDeviceBufferFOVEART colors;     /* rayCapacity x vec4 (rgb, depth_m); written by the engine */
  VkCommandBuffer commandBuffer;            /* record the trace here */
} XrFoveatedDeviceRayBatchFOVEART;

/*
 * Chained into every XrFoveatedDeviceRayBatchFOVEART's `next` (version 8):
 *
 * Footprint: XrFoveatedDeviceRayFootprintFOVEART, a float per ray, radians:
 *           the angle at the eye of the disc radius of the ray's point
 *           (thesis eq. 4; a pixel-grid point's own radius), written on the
 *           device with the rays. A ray stands for its point's disc: treat it
 *           as a cone of that half angle, whose radius at hit distance t is
 *           t * tan(footprint), to pick a texture level of detail. Same
 *           usage, queue and barriers as the rays.
 * Addresses: XrFoveatedDeviceRayAddressesFOVEART, each buffer range's
 *           VkDeviceAddress (buffer address + offset) when the app enabled
 *           bufferDeviceAddress on its device through
 *           xrCreateVulkanDeviceKHR (VkPhysicalDeviceVulkan12Features or
 *           VkPhysicalDeviceBufferDeviceAddressFeatures): the buffers then
 *           also have usage SHADER_DEVICE_ADDRESS. Otherwise every address
 *           is 0 and the usage absent. vkCmdTraceRaysIndirectKHR takes
 *           rayCount + 16 (XrFoveatedDeviceRayCountFOVEART::traceRays).
 */
#define XR_TYPE_FOVEATED_DEVICE_RAY_FOOTPRINT_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900008)
#define XR_TYPE_FOVEATED_DEVICE_RAY_ADDRESSES_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900009)

typedef struct XrFoveatedDeviceRayFootprintFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_DEVICE_RAY_FOOTPRINT_FOVEART */
  const void* XR_MAY_ALIAS next;
  XrFoveatedDeviceBufferFOVEART footprints; /* rayCapacity x float, radians; read only */
} XrFoveatedDeviceRayFootprintFOVEART;

typedef struct XrFoveatedDeviceRayAddressesFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_DEVICE_RAY_ADDRESSES_FOVEART */
  const void* XR_MAY_ALIAS next;
  VkDeviceAddress rayCount;   /* 0 without bufferDeviceAddress */
  VkDeviceAddress rays;
  VkDeviceAddress pointIndex;
  VkDeviceAddress colors;
  VkDeviceAddress footprints;
} XrFoveatedDeviceRayAddressesFOVEART;

typedef XrResult(XRAPI_PTR* PFN_xrFoveatedTraceRaysDeviceFOVEART)(void* userData,
                                                                 const XrFoveatedDeviceRayBatchFOVEART* batch);

/* Chain into XrFoveatedRendererCreateInfoFOVEART::next to register a device trace. */
typedef struct XrFoveatedDeviceTraceInfoFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_DEVICE_TRACE_INFO_FOVEART */
  const void* XR_MAY_ALIAS next;
  PFN_xrFoveatedTraceRaysDeviceFOVEART traceRaysDevice; /* required */
  void* userData;                                       /* passed back unchanged */
} XrFoveatedDeviceTraceInfoFOVEART;

/*
 * The app-recorded trace: the device trace for an engine that records its
 * trace in its own command buffers and submits them on a queue it chooses
 * (a render graph: Unreal's RDG, Unity's SRP, Godot's RenderingDevice).
 * Chain an XrFoveatedAppTraceInfoFOVEART into
 * XrFoveatedRendererCreateInfoFOVEART::next; traceRays may then be NULL.
 * Each frame, after xrLocateViews and before xrEndFrame:
 *
 *   xrAcquireFoveatedRayBatchFOVEART(renderer, &acquire, &batch);
 *   // record: wait batch.semaphore >= batch.raysReadyValue, trace
 *   // batch.views[v] (rays -> colors, as a device trace), then signal
 *   // batch.semaphore = batch.tracedValue; submit it on the app's queue.
 *   xrReleaseFoveatedRayBatchFOVEART(renderer, batch.batchId);
 *   xrEndFrame(...);  // the projection layer chains XrFoveatedRayTracingLayerFOVEART
 *
 * Why this shape: it is an OpenXR swapchain's acquire / use / release, for
 * buffers the layer writes and the app's GPU work reads and writes. As with
 * XR_FB_foveation_vulkan's fragment density maps, the layer owns the
 * resources and makes their contents, the app only uses them in command
 * buffers it records; unlike an image the runtime finishes before
 * xrWaitSwapchainImage returns, both sides are ahead on the GPU, so the order
 * is a timeline semaphore's values, never a host wait.
 *
 * Acquire:  once per frame, after xrWaitFrame and xrLocateViews (the
 *           displayTime, space and views of the frame's projection layer).
 *           The layer takes the gaze predicted for displayTime, plans each
 *           view and submits the rays of every view on the session's queue
 *           (XrGraphicsBindingVulkan2KHR), which then signals `semaphore` to
 *           raysReadyValue. A view the layer does not trace this frame
 *           (tables still being built, a view beyond two) has rayCapacity 0
 *           and null buffers: record nothing for it. The app's work must
 *           wait for raysReadyValue before it reads the rays (a
 *           VkTimelineSemaphoreSubmitInfo wait on its submission) and must
 *           signal tracedValue after its last write of the colours. The
 *           device needs Vulkan 1.2's timelineSemaphore, enabled through
 *           xrCreateVulkanDeviceKHR (else the create fails with
 *           XR_ERROR_VALIDATION_FAILURE). Like
 *           xrEndFrame, the acquire submits on the session's queue: the app
 *           must not use that queue from another thread during the call. A
 *           batch belongs to the next xrEndFrame whose projection layer names
 *           the renderer.
 * Release:  xrReleaseFoveatedRayBatchFOVEART(batchId) promises that the
 *           submission signalling tracedValue has been made (as
 *           xrReleaseSwapchainImage promises the app's rendering). Then
 *           xrEndFrame's one submission waits for tracedValue before it
 *           resolves the colours, reconstructs and encodes as a device trace.
 * Queue:    the rays are made and the colours read on the session's queue
 *           family. When queueFamilyIndices name another family, every buffer
 *           the renderer makes is VK_SHARING_MODE_CONCURRENT over those and
 *           the session's family (no ownership transfer to record on either
 *           side); else EXCLUSIVE on the session's family, and the app traces
 *           on any queue of it (another queue index is fine). An index that
 *           is no queue family of the device fails the create
 *           (XR_ERROR_VALIDATION_FAILURE). The semaphore is the layer's.
 * Lifetime: a batch's buffers stay valid until the frame's submission (the
 *           xrEndFrame after the acquire) finished, frame slot by frame slot
 *           as the device trace's ("Lifetime" there, frameIndex in each
 *           view); a view's `view` pointer and `next` chain (the footprint
 *           and addresses, as a device trace's) until the next acquire. When a
 *           slot's batch is acquired again, the slot's previous frame has
 *           finished on the device, the app's trace included (the layer's
 *           submission waited for it). The semaphore lives as long as the
 *           renderer; destroy the renderer only after the app's submissions
 *           that use it finished.
 * Gaze:     the rays are made at acquire, before the app records: the gaze
 *           is older at display than with a device trace (made at xrEndFrame)
 *           by the time from acquire to xrEndFrame, reported per frame in
 *           XrFoveatedAppTraceStatsFOVEART::acquireToEndFrameMs.
 * Errors:   a second acquire before the frame's xrEndFrame:
 *           XR_ERROR_CALL_ORDER_INVALID. A release of an unknown batchId, or
 *           a second release: XR_ERROR_VALIDATION_FAILURE (counted:
 *           rejectedReleases); a batch released twice before its xrEndFrame
 *           is retired there as an unreleased one (two releases promise two
 *           signals of one value: the layer relies on neither). A renderer created without the info struct:
 *           XR_ERROR_VALIDATION_FAILURE; one that reconstructs on the CPU
 *           (the config, a device the shaders cannot run on):
 *           XR_ERROR_FEATURE_UNSUPPORTED; viewCapacityInput too small:
 *           XR_ERROR_SIZE_INSUFFICIENT with viewCountOutput set. A batch not
 *           released by its frame's xrEndFrame is retired: its views show the
 *           app's own image (counted: unreleasedBatches, framesFallback,
 *           logged once), the layer never waits for its tracedValue, its
 *           semaphore is replaced for later batches (the old one lives until
 *           the renderer is destroyed: a late signal of it is harmless), and a
 *           later release of it returns XR_ERROR_CALL_ORDER_INVALID. A view
 *           whose pose, fov or size at xrEndFrame differs from the acquire's
 *           shows the app's own image (counted: mismatchedViews). Colours
 *           are judged on the device as a device trace's.
 * Both:     a frame without an acquired batch is traced through a chained
 *           device trace where the renderer has one, else its views show the
 *           app's own image; a frame with one, by the app. traceRays (the CPU
 *           callback) serves where the layer reconstructs on the CPU, where
 *           the acquire is refused. The device trace's callback model is this
 *           model with the layer as the app: the same rays, resolve and frame.
 */
#define XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900008)
#define XR_TYPE_FOVEATED_RAY_BATCH_ACQUIRE_INFO_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900009)
#define XR_TYPE_FOVEATED_RAY_BATCH_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900010)
#define XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART XR_FOVEART_STRUCTURE_TYPE(1000900011)

/* Chain into XrFoveatedRendererCreateInfoFOVEART::next to trace in the app's own command buffers. */
typedef struct XrFoveatedAppTraceInfoFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART */
  const void* XR_MAY_ALIAS next;
  uint32_t queueFamilyIndexCount;      /* families besides the session's that touch the buffers; may be 0 */
  const uint32_t* queueFamilyIndices;
} XrFoveatedAppTraceInfoFOVEART;

/* What a frame's rays are made for: the projection layer's display time, space and views. */
typedef struct XrFoveatedRayBatchAcquireInfoFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RAY_BATCH_ACQUIRE_INFO_FOVEART */
  const void* XR_MAY_ALIAS next;
  XrTime displayTime;             /* xrWaitFrame's predictedDisplayTime, as given to xrEndFrame */
  XrSpace space;                  /* the projection layer's space */
  uint32_t viewCount;             /* 1.. (views beyond two are not traced) */
  const XrView* views;            /* xrLocateViews in `space`: pose and fov per view */
  const XrExtent2Di* imageSizes;  /* per view, the imageRect extent the layer will be given */
} XrFoveatedRayBatchAcquireInfoFOVEART;

/* One frame's rays; views[v].commandBuffer is VK_NULL_HANDLE (the app records in its own). */
typedef struct XrFoveatedRayBatchFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_RAY_BATCH_FOVEART */
  void* XR_MAY_ALIAS next;
  uint64_t batchId;               /* nonzero; release with it */
  uint32_t viewCapacityInput;     /* elements of views */
  uint32_t viewCountOutput;       /* the acquire's viewCount, at most viewCapacityInput */
  XrFoveatedDeviceRayBatchFOVEART* views; /* written per view; rayCapacity 0: nothing to trace */
  VkSemaphore semaphore;          /* timeline, the layer's */
  uint64_t raysReadyValue;        /* wait for it before reading the rays */
  uint64_t tracedValue;           /* signal it after writing the colours */
} XrFoveatedRayBatchFOVEART;

/* Chain into XrFoveatedRendererStatsFOVEART::next: the app-recorded trace's counts since creation. */
typedef struct XrFoveatedAppTraceStatsFOVEART {
  XrStructureType type; /* XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART */
  void* XR_MAY_ALIAS next;
  uint64_t batchesAcquired;
  uint64_t unreleasedBatches;     /* retired at xrEndFrame unreleased or released twice: their views fell back */
  uint64_t rejectedReleases;      /* releases refused (unknown, twice, retired) */
  uint64_t mismatchedViews;       /* views whose pose, fov or size changed after the acquire: fell back */
  float acquireToEndFrameMs;      /* last frame: how much older the gaze is than with a device trace */
} XrFoveatedAppTraceStatsFOVEART;

typedef XrResult(XRAPI_PTR* PFN_xrAcquireFoveatedRayBatchFOVEART)(XrFoveatedRendererFOVEART renderer,
                                                                  const XrFoveatedRayBatchAcquireInfoFOVEART* acquireInfo,
                                                                  XrFoveatedRayBatchFOVEART* batch);
typedef XrResult(XRAPI_PTR* PFN_xrReleaseFoveatedRayBatchFOVEART)(XrFoveatedRendererFOVEART renderer,
                                                                  uint64_t batchId);
#endif /* XR_USE_GRAPHICS_API_VULKAN */

typedef XrResult(XRAPI_PTR* PFN_xrCreateFoveatedRendererFOVEART)(
    XrSession session, const XrFoveatedRendererCreateInfoFOVEART* createInfo,
    XrFoveatedRendererFOVEART* renderer);
typedef XrResult(XRAPI_PTR* PFN_xrDestroyFoveatedRendererFOVEART)(XrFoveatedRendererFOVEART renderer);
typedef XrResult(XRAPI_PTR* PFN_xrGetFoveatedRendererStatsFOVEART)(
    XrFoveatedRendererFOVEART renderer, XrFoveatedRendererStatsFOVEART* stats);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* XR_FOVEART_FOVEATED_RAY_TRACING_H */
