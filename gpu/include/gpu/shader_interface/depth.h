// Depth as the GPU path carries it (gpu/shader_depth.hpp on the host): the
// engine's distance along the ray in metres; none returned is
// FOVEART_DEPTH_UNKNOWN, a miss (the sky) FOVEART_DEPTH_FAR or more. No NaN or
// infinity reaches a shader: drivers may compile isnan/isinf away.
#ifndef FOVEART_SHADER_INTERFACE_DEPTH_H
#define FOVEART_SHADER_INTERFACE_DEPTH_H

#define FOVEART_DEPTH_UNKNOWN -1.0
#define FOVEART_DEPTH_FAR 1.0e30
// What the resolve writes for the sky, >= FOVEART_DEPTH_FAR (the host's kDepthFar).
#define FOVEART_DEPTH_SKY 3.0e38

#endif  // FOVEART_SHADER_INTERFACE_DEPTH_H
