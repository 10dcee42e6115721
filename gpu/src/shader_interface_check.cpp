// The one-definition check of the host/shader interface: every shader's
// push constants and buffer structs as glslang lays them out (reflection,
// shaders/interface_check.cmake) against the C++ structs of the same headers.
// A divergence fails this file's compilation, naming the shader and the member.
#include <cstddef>

#include "gpu/shader_interface/cache_device_rays.h"
#include "gpu/shader_interface/cache_pixels.h"
#include "gpu/shader_interface/cache_push.h"
#include "gpu/shader_interface/device_resolve.h"
#include "gpu/shader_interface/device_rays.h"
#include "gpu/shader_interface/encode.h"
#include "gpu/shader_interface/gather.h"
#include "gpu/shader_interface/ray_cache.h"
#include "gpu/shader_interface/scatter.h"
#include "gpu/shader_interface/temporal.h"
#include "shaders/layout_checks.h"
