// The scene flattened into the shader's std430 storage buffers (trace_core.glsl
// declares the same structs): triangles, per-triangle shading data, materials,
// lights, the scene constants, and which textures the materials sample (the
// images themselves: scene_textures.hpp).
#pragma once

#include "bvh.hpp"

#include <engine/effects.hpp>
#include <engine/scene.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace foveart::gpu_engine {

struct GpuTriangle {  // positions; material index; 1 when alpha-masked by a texture
  float p0[3];
  uint32_t material;
  float p1[3];
  uint32_t masked;
  float p2[3];
  uint32_t pad;
};
static_assert(sizeof(GpuTriangle) == 48);

struct GpuShading {  // vertex normals, face normal (in the w's), uv0 and uv1 of the three vertices
  float n0[3];
  float face_x;
  float n1[3];
  float face_y;
  float n2[3];
  float face_z;
  float uv[12];  // uv0[v0], uv0[v1] | uv0[v2], uv1[v0] | uv1[v1], uv1[v2]
};
static_assert(sizeof(GpuShading) == 96);

struct GpuMaterial {
  float base_color[4];
  float emissive[3];
  float metallic;
  float roughness;
  float alpha_cutoff;
  float transmission;
  float ior;
  int32_t texture;   // slot in scene_textures (SceneData::texture_slots), -1: none
  int32_t texcoord;  // 0 or 1
  int32_t alpha_mode;
  uint32_t texture_flags;  // its texture's wrap_s | wrap_t << 2 | nearest << 4 | srgb8 << 5 (kTextureSrgb8)
};
static_assert(sizeof(GpuMaterial) == 64);
inline constexpr uint32_t kTextureSrgb8 = 32;  // texture_flags: RGBA8 holding sRGB bytes (SceneTextures)

struct GpuLight {
  float position[3];
  uint32_t type;  // engine::LightType
  float direction[3];
  float range;
  float color[3];
  float intensity;
  float cos_inner;  // std::cos on the CPU, as light_incident computes them
  float cos_outer;
  float pad[2];
};
static_assert(sizeof(GpuLight) == 64);

struct GpuGlobals {
  float sky_zenith[3];
  float epsilon;
  float sky_horizon[3];
  uint32_t light_count;
  float ambient[3];
  uint32_t pad;
};
static_assert(sizeof(GpuGlobals) == 48);

struct SceneData {
  BvhData bvh;
  std::vector<GpuTriangle> triangles;  // indexed like Scene::mesh.triangles
  std::vector<GpuShading> shading;
  std::vector<GpuMaterial> materials;
  std::vector<GpuLight> lights;
  std::vector<uint32_t> texture_slots;  // per slot: its index into Scene::textures (those a material samples)
  GpuGlobals globals{};
  engine::Effects scene_effects;
};

// Checks the scene as engine::Tracer does (a texture index past the textures
// becomes "no texture"), builds the BVH and fills *out. False + *error on bad input.
[[nodiscard]] bool flatten_scene(engine::Scene& scene, SceneData* out, std::string* error);

}  // namespace foveart::gpu_engine
