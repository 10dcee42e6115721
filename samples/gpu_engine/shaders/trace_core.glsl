// The GPU port of engine::Tracer (samples/engine/src/tracer.cpp, shading.hpp,
// texture_sampler.hpp): the Whitted shading model term by term, its recursion
// unrolled into a small stack of pending rays, over a scene query chosen at
// compile time: the compute tracer's BVH traversal (scene_bvh.glsl) or, with
// FOVEART_RT_PIPELINE defined, traceRayEXT on VK_KHR_ray_tracing_pipeline
// (scene_rt.glsl). The shading code exists once, here. Scene buffers in set 0
// (scene_data.glsl; samples/gpu_engine/src/scene_data.hpp declares the same
// std430 structs).
#ifndef FOVEART_GPU_TRACE_CORE_GLSL
#define FOVEART_GPU_TRACE_CORE_GLSL

// Effects (engine::Effects::bits) and max_depth: one pipeline per tracer.
layout(constant_id = 0) const uint EFFECTS = 15u;
layout(constant_id = 1) const int MAX_DEPTH = 4;
const bool FX_SHADOWS = (EFFECTS & 1u) != 0u;
const bool FX_REFLECTION = (EFFECTS & 2u) != 0u;
const bool FX_REFRACTION = (EFFECTS & 4u) != 0u;
const bool FX_TEXTURES = (EFFECTS & 8u) != 0u;

// Depth first, a Whitted tree leaves at most one pending ray per level and two at the
// deepest: MAX_DEPTH + 1 (its rays spawn none past MAX_DEPTH).
const int PENDING_STACK = MAX_DEPTH + 1;
const float INV_PI = 0.318309886;
const float MIRROR_ROUGHNESS = 0.5;

#include "scene_data.glsl"
#ifdef FOVEART_RT_PIPELINE
#include "scene_rt.glsl"
#else
#include "scene_bvh.glsl"
#endif

// ---- shading.hpp -----------------------------------------------------------------

bool reflective(Material m) { return m.roughness <= MIRROR_ROUGHNESS; }
bool transmissive(Material m) { return m.transmission > 0.0 || (m.alpha_mode == 2 && m.base_color.a < 1.0); }

vec3 fresnel_schlick(vec3 f0, float cos_theta) {
  const float m = 1.0 - clamp(cos_theta, 0.0, 1.0);
  const float m2 = m * m;
  return f0 + (vec3(1.0) - f0) * (m2 * m2 * m);
}

float dielectric_f0(float ior) {
  const float r = (ior - 1.0) / (ior + 1.0);
  return r * r;
}

vec3 reflection_weight(Material m, vec3 base, float cos_theta) {
  if (!reflective(m)) return vec3(0.0);
  const vec3 f0 = glm_mix3(vec3(dielectric_f0(m.ior)), base, m.metallic);
  const float smooth_ = 1.0 - m.roughness / MIRROR_ROUGHNESS;
  return fresnel_schlick(f0, cos_theta) * smooth_;
}

float diffuse_weight(Material m) {
  const float opaque = 1.0 - m.transmission;
  return reflective(m) ? (1.0 - m.metallic) * opaque : opaque;
}

vec3 light_incident(Light l, vec3 p, out vec3 out_l, out float out_dist) {
  if (l.type == 2u) {
    out_l = -l.direction;
    out_dist = positive_infinity();
    return l.color * l.intensity;
  }
  const vec3 d = l.position - p;
  const float dist2 = max(dot(d, d), 1e-8);
  const float dist = sqrt(dist2);
  out_l = d / dist;
  out_dist = dist;
  float atten = 1.0 / dist2;
  if (l.range > 0.0) {
    const float r = dist / l.range;
    const float w = clamp(1.0 - r * r * r * r, 0.0, 1.0);
    atten *= w * w;
  }
  if (l.type == 1u) {
    const float cd = dot(l.direction, -out_l);
    const float t = clamp((cd - l.cos_outer) / max(l.cos_inner - l.cos_outer, 1e-4), 0.0, 1.0);
    atten *= t * t;
  }
  return l.color * (l.intensity * atten);
}

vec3 sky_radiance(vec3 dir) { return glm_mix3(sky_horizon, sky_zenith, max(dir.y, 0.0)); }

// ---- the Whitted path of one ray ----------------------------------------------------

struct Pending {
  vec3 origin;
  vec3 dir;
  vec3 weight;
  int depth;
};

// The traced ray's footprint in radians (XrFoveatedDeviceRayFootprintFOVEART; batch_trace.glsl
// sets it): its primary hit samples textures at the cone's level of detail. 0: level 0, as the CPU engine.
float ray_footprint_rad = 0.0;

// Radiance along (o, d) as Tracer::Impl::trace and trace_packet compute it: rgb
// (finite, >= 0) and in w the primary hit distance (+inf: a miss; NaN: an
// invalid ray, black). rays.xyz += shadow, reflection, refraction rays cast.
vec4 trace_path(vec3 o, vec3 d_in, inout uvec3 rays) {
  const float len2 = dot(d_in, d_in);
  if (!(len2 > 0.0) || !finite(len2) || !finite(o.x + o.y + o.z)) return vec4(0.0, 0.0, 0.0, uintBitsToFloat(0x7fc00000u));
  const vec3 d0 = d_in * (1.0 / sqrt(len2));
  vec3 color = vec3(0.0);
  float depth_m = positive_infinity();
  Pending stack[PENDING_STACK];
  int sp = 0;
  stack[sp++] = Pending(o, d0, vec3(1.0), 0);
  while (sp > 0) {
    const Pending p = stack[--sp];
    float t, u, v;
    uint tri;
    const bool hit = scene_closest_hit(p.origin, p.dir, positive_infinity(), t, u, v, tri);
    if (p.depth == 0) depth_m = hit ? t : positive_infinity();
    if (!hit) {
      color += p.weight * sky_radiance(p.dir);
      continue;
    }
    const Triangle tr = tris[tri];
    const Shading s = shading[tri];
    const Material m = materials[tr.material];
    const vec3 pos = p.origin + t * p.dir;
    vec3 n = (1.0 - u - v) * s.n0.xyz + u * s.n1.xyz + v * s.n2.xyz;
    const float nlen2 = dot(n, n);
    n = nlen2 > 1e-12 ? n * (1.0 / sqrt(nlen2)) : vec3(s.n0.w, s.n1.w, s.n2.w);
    const bool front = dot(p.dir, n) < 0.0;  // entering the surface (for refraction)
    if (!front) n = -n;                      // shade the side the ray sees
    const float cos_view = -dot(p.dir, n);
    vec3 base = m.base_color.rgb;
    if (FX_TEXTURES && m.texture >= 0) {
      const float lod = p.depth == 0 && ray_footprint_rad > 0.0
                            ? cone_texture_lod(tri, m.texcoord, m.texture, t, ray_footprint_rad, cos_view)
                            : 0.0;
      base *= sample_texture_lod(m.texture, m.texture_flags, texcoord(tri, m.texcoord, u, v), lod).rgb;
    }
    const float kd = diffuse_weight(m);
    const float ambient_shape = 0.4 + 0.6 * cos_view;
    color += p.weight * (m.emissive + base * (kd * ambient_shape) * ambient);

    if (FX_SHADOWS && kd > 0.0) {
      for (uint li = 0u; li < light_count; ++li) {
        vec3 l;
        float dist;
        const vec3 radiance = light_incident(lights[li], pos, l, dist);
        const float cos_l = dot(n, l);
        if (cos_l <= 0.0 || radiance == vec3(0.0)) continue;
        const vec3 contrib = p.weight * base * (kd * INV_PI * cos_l) * radiance;
        const float tfar = isinf(dist) ? dist : max(dist - 2.0 * epsilon, 0.0);
        ++rays.x;
        if (!scene_occluded(pos + n * epsilon, l, tfar)) color += contrib;
      }
    }

    if (p.depth >= MAX_DEPTH) continue;
    bool has_reflection = false, has_refraction = false;
    Pending reflection_ray, refraction_ray;
    if (FX_REFLECTION && reflective(m)) {
      const vec3 w = p.weight * reflection_weight(m, base, cos_view);
      if (max(w.x, max(w.y, w.z)) >= 1e-3) {
        has_reflection = true;
        reflection_ray = Pending(pos + n * epsilon, glm_reflect(p.dir, n), w, p.depth + 1);
      }
    }
    if (FX_REFRACTION && transmissive(m)) {
      vec3 w = vec3(0.0);
      vec3 dir = p.dir;
      vec3 origin = pos + p.dir * epsilon;
      if (m.transmission > 0.0) {
        // Snell refraction; without the reflection effect the Fresnel split is dropped.
        const float eta = front ? 1.0 / m.ior : m.ior;
        vec3 tdir = glm_refract(p.dir, n, eta);
        if (dot(tdir, tdir) == 0.0) tdir = glm_reflect(p.dir, n);  // total internal reflection
        dir = glm_normalize(tdir);
        origin = pos + (dot(dir, n) < 0.0 ? -n : n) * epsilon;
        vec3 kt = base * m.transmission;
        if (FX_REFLECTION) kt *= vec3(1.0) - reflection_weight(m, base, cos_view);
        w = p.weight * kt;
      } else {  // alpha blending: the ray continues straight through
        w = p.weight * (1.0 - m.base_color.a);
      }
      if (max(w.x, max(w.y, w.z)) >= 1e-3) {
        has_refraction = true;
        refraction_ray = Pending(origin, dir, w, p.depth + 1);
      }
    }
    // The CPU traces the reflection subtree before the refraction one: pop in that order.
    if (has_refraction && sp < PENDING_STACK) {
      ++rays.z;
      stack[sp++] = refraction_ray;
    }
    if (has_reflection && sp < PENDING_STACK) {
      ++rays.y;
      stack[sp++] = reflection_ray;
    }
  }
  if (!finite(color.x + color.y + color.z)) color = vec3(0.0);
  return vec4(max(color, vec3(0.0)), depth_m);
}

#ifdef FOVEART_RT_PIPELINE
// ---- ray counters: one atomic per kind and launch (no workgroups in a ray-generation shader)

void begin_counting() {}

void count_rays(uint primary, uvec3 secondary) {
  if (primary != 0u) atomicAdd(counters[0], primary);
  if (secondary.x != 0u) atomicAdd(counters[1], secondary.x);
  if (secondary.y != 0u) atomicAdd(counters[2], secondary.y);
  if (secondary.z != 0u) atomicAdd(counters[3], secondary.z);
}

void end_counting() {}
#else
// ---- ray counters: summed per workgroup, one atomic per kind and group ------------
// group_rays[4], [5]: the group's traversal work (COUNT_WORK), added to the 64-bit
// counters[4, 5] and [6, 7] with the carry into the high word.

shared uint group_rays[6];

void begin_counting() {
  if (gl_LocalInvocationIndex < 6u) group_rays[gl_LocalInvocationIndex] = 0u;
  barrier();
}

void count_rays(uint primary, uvec3 secondary) {
  if (primary != 0u) atomicAdd(group_rays[0], primary);
  if (secondary.x != 0u) atomicAdd(group_rays[1], secondary.x);
  if (secondary.y != 0u) atomicAdd(group_rays[2], secondary.y);
  if (secondary.z != 0u) atomicAdd(group_rays[3], secondary.z);
}

// counters[low, low + 1] += value as one 64-bit count.
void add_wide(uint low, uint value) {
  const uint before = atomicAdd(counters[low], value);
  if (before + value < before) atomicAdd(counters[low + 1u], 1u);
}

void end_counting() {
  if (COUNT_WORK != 0u) {
    if (work_nodes != 0u) atomicAdd(group_rays[4], work_nodes);
    if (work_triangles != 0u) atomicAdd(group_rays[5], work_triangles);
  }
  barrier();
  const uint i = gl_LocalInvocationIndex;
  if (i < 4u && group_rays[i] != 0u) atomicAdd(counters[i], group_rays[i]);
  if (COUNT_WORK != 0u && i >= 4u && i < 6u && group_rays[i] != 0u) add_wide(4u + 2u * (i - 4u), group_rays[i]);
}

#endif

#endif
