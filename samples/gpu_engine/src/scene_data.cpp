// Scene -> std430 arrays: the data engine::Tracer reads per hit (tracer.cpp,
// shading.hpp, texture_sampler.hpp), laid out for trace_core.glsl.
#include "scene_data.hpp"
#include "vk_helpers.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace foveart::gpu_engine {
namespace {

void put3(float (&dst)[3], glm::vec3 v) {
  dst[0] = v.x;
  dst[1] = v.y;
  dst[2] = v.z;
}

// Triangles and their shading data; returns those that go into the BVH: as
// engine::Tracer::build, a MASK material without texture is decided here, one
// with a texture per hit.
std::vector<uint32_t> flatten_triangles(const engine::Scene& scene, SceneData* out) {
  const engine::Mesh& m = scene.mesh;
  out->triangles.resize(m.triangles.size());
  out->shading.resize(m.triangles.size());
  std::vector<uint32_t> traced;
  traced.reserve(m.triangles.size());
  auto uv_at = [](const std::vector<glm::vec2>& uvs, uint32_t v) { return uvs.empty() ? glm::vec2(0.0f) : uvs[v]; };
  for (uint32_t i = 0; i < m.triangles.size(); ++i) {
    const glm::uvec3 t = m.triangles[i];
    const engine::Material& mat = scene.materials[m.triangle_material[i]];
    GpuTriangle& g = out->triangles[i];
    put3(g.p0, m.positions[t.x]);
    put3(g.p1, m.positions[t.y]);
    put3(g.p2, m.positions[t.z]);
    g.material = m.triangle_material[i];
    g.masked = mat.alpha_mode == engine::AlphaMode::kMask && mat.base_color_texture >= 0 ? 1u : 0u;
    g.pad = 0;
    if (mat.alpha_mode != engine::AlphaMode::kMask || mat.base_color_texture >= 0 ||
        mat.base_color.a >= mat.alpha_cutoff)
      traced.push_back(i);
    GpuShading& s = out->shading[i];
    const glm::vec3 face =
        glm::normalize(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
    put3(s.n0, m.normals[t.x]);
    put3(s.n1, m.normals[t.y]);
    put3(s.n2, m.normals[t.z]);
    s.face_x = face.x;
    s.face_y = face.y;
    s.face_z = face.z;
    const glm::vec2 uvs[6] = {uv_at(m.uv0, t.x), uv_at(m.uv0, t.y), uv_at(m.uv0, t.z),
                              uv_at(m.uv1, t.x), uv_at(m.uv1, t.y), uv_at(m.uv1, t.z)};
    for (int k = 0; k < 6; ++k) {
      s.uv[2 * k] = uvs[k].x;
      s.uv[2 * k + 1] = uvs[k].y;
    }
  }
  return traced;
}

void flatten_materials(const engine::Scene& scene, SceneData* out) {
  out->materials.clear();
  for (const engine::Material& mat : scene.materials) {
    GpuMaterial g{};
    for (int k = 0; k < 4; ++k) g.base_color[k] = mat.base_color[k];
    put3(g.emissive, mat.emissive);
    g.metallic = mat.metallic;
    g.roughness = mat.roughness;
    g.alpha_cutoff = mat.alpha_cutoff;
    g.transmission = mat.transmission;
    g.ior = mat.ior;
    g.texture = mat.base_color_texture;
    if (g.texture >= 0) {
      const engine::Texture& t = scene.textures[static_cast<size_t>(g.texture)];
      g.texture_flags = static_cast<uint32_t>(t.wrap_s) | static_cast<uint32_t>(t.wrap_t) << 2 | (t.nearest ? 16u : 0u);
    }
    g.texcoord = mat.base_color_texcoord;
    g.alpha_mode = static_cast<int32_t>(mat.alpha_mode);
    out->materials.push_back(g);
  }
}

void flatten_lights(const engine::Scene& scene, SceneData* out) {
  out->lights.clear();
  for (const engine::Light& l : scene.lights) {
    GpuLight g{};
    put3(g.position, l.position);
    g.type = static_cast<uint32_t>(l.type);
    put3(g.direction, l.direction);
    g.range = l.range;
    put3(g.color, l.color);
    g.intensity = l.intensity;
    g.cos_inner = std::cos(l.inner_cone_rad);
    g.cos_outer = std::cos(l.outer_cone_rad);
    out->lights.push_back(g);
  }
}

// The textures the materials sample, each once, in slots in order of first
// use; the materials refer to slots (unused textures are not uploaded).
void assign_texture_slots(const engine::Scene& scene, SceneData* out) {
  out->texture_slots.clear();
  std::vector<int32_t> slot_of(scene.textures.size(), -1);
  for (GpuMaterial& g : out->materials) {
    if (g.texture < 0) continue;
    int32_t& slot = slot_of[static_cast<size_t>(g.texture)];
    if (slot < 0) {
      slot = static_cast<int32_t>(out->texture_slots.size());
      out->texture_slots.push_back(static_cast<uint32_t>(g.texture));
    }
    g.texture = slot;
  }
}

}  // namespace

bool flatten_scene(engine::Scene& scene, SceneData* out, std::string* error) {
  if (!engine::prepare_scene(scene, error)) return false;
  out->scene_effects = engine::derive_effects(scene);
  const std::vector<uint32_t> traced = flatten_triangles(scene, out);
  if (!build_bvh(scene.mesh, traced, &out->bvh, error)) return false;
  flatten_materials(scene, out);
  flatten_lights(scene, out);
  assign_texture_slots(scene, out);
  const engine::Bounds b = engine::scene_bounds(scene.mesh);
  GpuGlobals& g = out->globals;
  put3(g.sky_zenith, scene.sky_zenith);
  put3(g.sky_horizon, scene.sky_horizon);
  put3(g.ambient, scene.ambient);
  g.epsilon = 1e-4f * std::max(1.0f, glm::length(b.max - b.min));  // engine::Tracer's epsilon
  g.light_count = static_cast<uint32_t>(scene.lights.size());
  return true;
}

}  // namespace foveart::gpu_engine
