// The common subset the host/shader interface headers here are written in:
// each is included by the GLSL (GL_GOOGLE_include_directive, -I gpu/include)
// and by the C++, so a block, struct, flag or sentinel is defined once.
//
// In C++ the GLSL types become layout-equal structs in foveart::gpu::shader
// with std430's alignments (vec2 8, vec4 16); vec3 is left out (std430 gives
// it 16-byte alignment but a 12-byte size, which no C++ struct reproduces).
// The build checks every member's offset and every struct's size against
// glslang's reflection of the compiled shaders (shaders/interface_check.cmake).
//
//   FOVEART_PUSH_CONSTANTS(Name) { members };   a push-constant block / struct Name
//   struct Name { members };                    a buffer element, the same in both
//   #define FOVEART_..._BIT 1u                  flags and sentinels (1u is C++ too)
//   FOVEART_FUNCTION void f(uint a, FOVEART_OUT(uint) b) { ... }
//                                               arithmetic both run (uint, ?:, no library calls)
#ifndef FOVEART_SHADER_INTERFACE_GLSL_CPP_H
#define FOVEART_SHADER_INTERFACE_GLSL_CPP_H

#ifdef __cplusplus
#include <cstdint>

namespace foveart::gpu::shader {
using uint = std::uint32_t;
struct alignas(8) vec2 {
  float x, y;
};
struct alignas(16) vec4 {
  float x, y, z, w;
};
struct alignas(8) ivec2 {
  std::int32_t x, y;
};
struct alignas(8) uvec2 {
  std::uint32_t x, y;
};
struct alignas(16) uvec4 {
  std::uint32_t x, y, z, w;
};
}  // namespace foveart::gpu::shader

#define FOVEART_SHADER_INTERFACE_BEGIN namespace foveart::gpu::shader {
#define FOVEART_SHADER_INTERFACE_END }
#define FOVEART_PUSH_CONSTANTS(name) struct name
#define FOVEART_FUNCTION inline
#define FOVEART_OUT(type) type&
#else
#define FOVEART_SHADER_INTERFACE_BEGIN
#define FOVEART_SHADER_INTERFACE_END
#define FOVEART_PUSH_CONSTANTS(name) layout(push_constant) uniform name
#define FOVEART_FUNCTION
#define FOVEART_OUT(type) out type
#endif

#endif  // FOVEART_SHADER_INTERFACE_GLSL_CPP_H
