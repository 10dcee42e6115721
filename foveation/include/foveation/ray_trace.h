/*
 * FoveaRT engine callback contract (C ABI).
 *
 * FoveaRT never shades pixels for a foveated view. It asks the engine one
 * question: "what colour do these rays see?". The engine answers through a
 * FoveartTraceRaysFn it registers (with the sample engine in samples/engine,
 * or through the layer's XR_FOVEART_foveated_ray_tracing extension).
 *
 * Threads:   the callback is called from several worker threads at once, each
 *            with its own disjoint batch. The engine must be thread-safe; it
 *            must not retain any pointer from a batch after returning.
 * Units:     positions in metres in the application's tracking space (the
 *            XrSpace the projection layer was submitted in); directions are unit
 *            vectors; screen positions in pixels of the eye's image, origin at the
 *            top-left pixel corner, x right, y down (pixel centres at .5).
 * Colours:   linear RGB, one float triple per ray, written to out_rgb. Values
 *            must be finite and >= 0; FoveaRT treats NaN/Inf as a failed ray.
 * Errors:    return FOVEART_RESULT_SUCCESS or a negative FoveartResult. Never
 *            let a C++ exception cross this boundary: catch inside the engine.
 * Growth:    every struct starts with (type, size); consumers check both and
 *            read only the prefix they know, so new fields append at the end.
 */
#ifndef FOVEATION_RAY_TRACE_H
#define FOVEATION_RAY_TRACE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum FoveartResult {
  FOVEART_RESULT_SUCCESS = 0,
  FOVEART_RESULT_ERROR_INVALID_ARGUMENT = -1, /* a batch the engine cannot read */
  FOVEART_RESULT_ERROR_ENGINE_FAILURE = -2,   /* the engine failed (caught exception, ...) */
  FOVEART_RESULT_ERROR_OUT_OF_MEMORY = -3,
  FOVEART_RESULT_MAX_ENUM = 0x7FFFFFFF
} FoveartResult;

typedef enum FoveartStructureType {
  FOVEART_TYPE_EYE_VIEW = 1,
  FOVEART_TYPE_RAY_BATCH = 2,
  FOVEART_TYPE_MAX_ENUM = 0x7FFFFFFF
} FoveartStructureType;

/* One eye's view: pose in tracking space and an asymmetric frustum, as in
 * XrView (angles in radians, left/down negative). */
typedef struct FoveartEyeView {
  uint32_t type; /* FOVEART_TYPE_EYE_VIEW */
  uint32_t size; /* sizeof(FoveartEyeView) as compiled by the producer */
  uint32_t eye_index; /* 0 = left, 1 = right */
  uint32_t width_px;
  uint32_t height_px;
  float position_m[3];
  float orientation_xyzw[4];
  float angle_left_rad;
  float angle_right_rad;
  float angle_up_rad;
  float angle_down_rad;
} FoveartEyeView;

/* A batch of rays for one eye. All arrays hold ray_count entries. */
typedef struct FoveartRayBatch {
  uint32_t type; /* FOVEART_TYPE_RAY_BATCH */
  uint32_t size; /* sizeof(FoveartRayBatch) as compiled by the producer */
  uint64_t frame_index;
  const FoveartEyeView* view;
  uint32_t ray_count;
  uint32_t reserved0;
  const float* origins_m;    /* xyz per ray, tracking space */
  const float* directions;   /* xyz per ray, unit length, tracking space */
  const float* sample_px;    /* xy per ray, screen position of the ray in the eye image */
  const uint32_t* point_index; /* per ray: the point (of the point set) it belongs to */
  float* out_rgb;            /* rgb per ray, written by the engine */
  /* Optional, when size >= FOVEART_RAY_BATCH_SIZE_WITH_DEPTH: distance in metres
   * along each ray to what it hit (+INFINITY for a miss). FoveaRT fills it with
   * NaN before the call; an engine that leaves it so gets a rotation-only history
   * reprojection, one that fills it gets parallax-correct reprojection. */
  float* out_depth_m;
} FoveartRayBatch;

/* The size of a batch that carries out_depth_m (engines built against an older
 * header see a larger size and simply never write it). */
#define FOVEART_RAY_BATCH_SIZE_WITH_DEPTH (offsetof(FoveartRayBatch, out_depth_m) + sizeof(float*))

/* The engine callback. user_data is what the engine registered with it. */
typedef int32_t (*FoveartTraceRaysFn)(void* user_data, const FoveartRayBatch* batch);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* FOVEATION_RAY_TRACE_H */
