// Whitted-style shading terms shared by the tracing kernels.
#pragma once

#include <engine/scene.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace foveart::engine {

inline constexpr float kInvPi = 0.318309886f;

// Schlick's approximation of the Fresnel reflectance (Schlick 1994).
inline glm::vec3 fresnel_schlick(glm::vec3 f0, float cos_theta) {
  const float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
  const float m2 = m * m;
  return f0 + (glm::vec3(1.0f) - f0) * (m2 * m2 * m);
}

inline float dielectric_f0(float ior) {
  const float r = (ior - 1.0f) / (ior + 1.0f);
  return r * r;
}

// Weight of the mirror reflection of a smooth material (zero for rough ones).
inline glm::vec3 reflection_weight(const Material& m, glm::vec3 base, float cos_theta) {
  if (!m.reflective()) return glm::vec3(0.0f);
  const glm::vec3 f0 = glm::mix(glm::vec3(dielectric_f0(m.ior)), base, m.metallic);
  const float smooth = 1.0f - m.roughness / Material::kMirrorRoughness;
  return fresnel_schlick(f0, cos_theta) * smooth;
}

// Share of Lambertian diffuse; rough metals are shaded as diffuse base colour.
inline float diffuse_weight(const Material& m) {
  const float opaque = 1.0f - m.transmission;
  return m.reflective() ? (1.0f - m.metallic) * opaque : opaque;
}

// Radiance arriving from a punctual light (KHR_lights_punctual conventions):
// direction to the light in *out_l, distance in *out_dist (inf for directional).
inline glm::vec3 light_incident(const Light& l, glm::vec3 p, glm::vec3* out_l, float* out_dist) {
  if (l.type == LightType::kDirectional) {
    *out_l = -l.direction;
    *out_dist = INFINITY;
    return l.color * l.intensity;
  }
  const glm::vec3 d = l.position - p;
  const float dist2 = std::max(glm::dot(d, d), 1e-8f);
  const float dist = std::sqrt(dist2);
  *out_l = d / dist;
  *out_dist = dist;
  float atten = 1.0f / dist2;  // inverse square law
  if (l.range > 0.0f) {        // glTF's recommended smooth range window
    const float r = dist / l.range;
    const float w = std::clamp(1.0f - r * r * r * r, 0.0f, 1.0f);
    atten *= w * w;
  }
  if (l.type == LightType::kSpot) {
    const float cos_outer = std::cos(l.outer_cone_rad);
    const float cos_inner = std::cos(l.inner_cone_rad);
    const float cd = glm::dot(l.direction, -*out_l);
    const float t = std::clamp((cd - cos_outer) / std::max(cos_inner - cos_outer, 1e-4f), 0.0f, 1.0f);
    atten *= t * t;
  }
  return l.color * (l.intensity * atten);
}

inline glm::vec3 sky_radiance(const Scene& s, glm::vec3 dir) {
  return glm::mix(s.sky_horizon, s.sky_zenith, std::max(dir.y, 0.0f));
}

}  // namespace foveart::engine
