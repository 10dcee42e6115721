// The GPU port of engine::Tracer (samples/engine/src/tracer.cpp, shading.hpp,
// texture_sampler.hpp): BVH traversal (closest hit, any hit for shadow rays)
// with the alpha-mask test, and the Whitted shading model term by term, its
// recursion unrolled into a small stack of pending rays. Scene buffers in set 0
// (samples/gpu_engine/src/scene_data.hpp declares the same std430 structs).
#ifndef FOVEART_GPU_TRACE_CORE_GLSL
#define FOVEART_GPU_TRACE_CORE_GLSL

// Effects (engine::Effects::bits) and max_depth: one pipeline per tracer.
layout(constant_id = 0) const uint EFFECTS = 15u;
layout(constant_id = 1) const int MAX_DEPTH = 4;
const bool FX_SHADOWS = (EFFECTS & 1u) != 0u;
const bool FX_REFLECTION = (EFFECTS & 2u) != 0u;
const bool FX_REFRACTION = (EFFECTS & 4u) != 0u;
const bool FX_TEXTURES = (EFFECTS & 8u) != 0u;

const uint LEAF_BIT = 0x80000000u;
const uint EMPTY_CHILD = LEAF_BIT;
const int BVH_STACK = 64;      // > kMaxBvhDepth (bvh.hpp)
const int PENDING_STACK = 16;  // > GpuTracerOptions::kMaxDepth + 1
const float INV_PI = 0.318309886;
const float MIRROR_ROUGHNESS = 0.5;

struct Node {
  vec3 lmin;
  uint left;
  vec3 lmax;
  uint pad0;
  vec3 rmin;
  uint right;
  vec3 rmax;
  uint pad1;
};
struct Triangle {
  vec3 p0;
  uint material;
  vec3 p1;
  uint masked;
  vec3 p2;
  uint pad;
};
struct Shading {
  vec4 n0;  // w: face normal x
  vec4 n1;  // w: face normal y
  vec4 n2;  // w: face normal z
  vec4 uva;  // uv0[v0], uv0[v1]
  vec4 uvb;  // uv0[v2], uv1[v0]
  vec4 uvc;  // uv1[v1], uv1[v2]
};
struct Material {
  vec4 base_color;
  vec3 emissive;
  float metallic;
  float roughness;
  float alpha_cutoff;
  float transmission;
  float ior;
  int texture;
  int texcoord;
  int alpha_mode;  // 0 opaque, 1 mask, 2 blend
  int pad;
};
struct Light {
  vec3 position;
  uint type;  // 0 point, 1 spot, 2 directional
  vec3 direction;
  float range;
  vec3 color;
  float intensity;
  float cos_inner;
  float cos_outer;
  vec2 pad;
};
struct TextureInfo {
  uint offset;
  uint width;
  uint height;
  uint flags;  // wrap_s | wrap_t << 2 | nearest << 4
};

layout(std430, set = 0, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, set = 0, binding = 1) readonly buffer Prims { uint prims[]; };
layout(std430, set = 0, binding = 2) readonly buffer Triangles { Triangle tris[]; };
layout(std430, set = 0, binding = 3) readonly buffer Shadings { Shading shading[]; };
layout(std430, set = 0, binding = 4) readonly buffer Materials { Material materials[]; };
layout(std430, set = 0, binding = 5) readonly buffer Lights { Light lights[]; };
layout(std430, set = 0, binding = 6) readonly buffer Textures { TextureInfo textures[]; };
layout(std430, set = 0, binding = 7) readonly buffer Texels { vec4 texels[]; };
layout(std430, set = 0, binding = 8) readonly buffer Globals {
  vec3 sky_zenith;
  float epsilon;
  vec3 sky_horizon;
  uint light_count;
  vec3 ambient;
  uint globals_pad;
};
// primary, shadow, reflection, refraction
layout(std430, set = 0, binding = 9) buffer Counters { uint counters[4]; };

float positive_infinity() { return uintBitsToFloat(0x7f800000u); }
bool finite(float x) { return !isnan(x) && !isinf(x); }

// glm's formulas (the CPU engine's), so both round alike.
vec3 glm_cross(vec3 x, vec3 y) { return vec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y); }
vec3 glm_mix3(vec3 x, vec3 y, float a) { return x * (1.0 - a) + y * a; }
vec4 glm_mix4(vec4 x, vec4 y, float a) { return x * (1.0 - a) + y * a; }
vec3 glm_normalize(vec3 v) { return v * (1.0 / sqrt(dot(v, v))); }
vec3 glm_reflect(vec3 i, vec3 n) { return i - n * dot(n, i) * 2.0; }
vec3 glm_refract(vec3 i, vec3 n, float eta) {
  const float d = dot(n, i);
  const float k = 1.0 - eta * eta * (1.0 - d * d);
  return k >= 0.0 ? eta * i - (eta * d + sqrt(k)) * n : vec3(0.0);
}
// glm::quat * vec3.
vec3 glm_rotate(vec4 q_xyzw, vec3 v) {
  const vec3 uv = glm_cross(q_xyzw.xyz, v);
  const vec3 uuv = glm_cross(q_xyzw.xyz, uv);
  return v + ((uv * q_xyzw.w) + uuv) * 2.0;
}

// ---- texture_sampler.hpp -------------------------------------------------------

int c_rem(int a, int n) { return a - (a / n) * n; }  // C's %: truncating division

// wrap_texel: 0 repeat, 1 clamp, 2 mirror.
int wrap_texel(int i, int n, uint mode) {
  if (mode == 1u) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  if (mode == 2u) {
    const int period = 2 * n;
    int m = c_rem(i, period);
    if (m < 0) m += period;
    return m < n ? m : period - 1 - m;
  }
  const int m = c_rem(i, n);
  return m < 0 ? m + n : m;
}

vec4 texel_at(TextureInfo t, int xi, int yi) {
  const uint y = uint(wrap_texel(yi, int(t.height), (t.flags >> 2u) & 3u));
  const uint x = uint(wrap_texel(xi, int(t.width), t.flags & 3u));
  return texels[t.offset + y * t.width + x];
}

// sample_texture: bilinear (or nearest), uv origin top-left.
vec4 sample_texture(int index, vec2 uv) {
  const TextureInfo t = textures[index];
  if (!finite(uv.x) || !finite(uv.y)) uv = vec2(0.0);
  uv = clamp(uv, vec2(-1.0e6), vec2(1.0e6));
  const float x = uv.x * float(t.width) - 0.5;
  const float y = uv.y * float(t.height) - 0.5;
  const float fx0 = floor(x);
  const float fy0 = floor(y);
  const int x0 = int(fx0);
  const int y0 = int(fy0);
  if ((t.flags & 16u) != 0u) return texel_at(t, int(floor(x + 0.5)), int(floor(y + 0.5)));
  const float ax = x - fx0;
  const float ay = y - fy0;
  return glm_mix4(glm_mix4(texel_at(t, x0, y0), texel_at(t, x0 + 1, y0), ax),
                  glm_mix4(texel_at(t, x0, y0 + 1), texel_at(t, x0 + 1, y0 + 1), ax), ay);
}

// Tracer::Impl::texcoord.
vec2 texcoord(uint tri, int set, float u, float v) {
  const Shading s = shading[tri];
  if (set == 0) return (1.0 - u - v) * s.uva.xy + u * s.uva.zw + v * s.uvb.xy;
  return (1.0 - u - v) * s.uvb.zw + u * s.uvc.xy + v * s.uvc.zw;
}

// Tracer::Impl::alpha_passes (glTF alphaMode MASK).
bool alpha_passes(uint tri, float u, float v) {
  const Material m = materials[tris[tri].material];
  float alpha = m.base_color.a;
  if (m.texture >= 0) alpha *= sample_texture(m.texture, texcoord(tri, m.texcoord, u, v)).a;
  return alpha >= m.alpha_cutoff;
}

// ---- traversal -------------------------------------------------------------------

// Moeller-Trumbore in Embree 3's form (triangle_intersector_moeller.h): hit
// with t in (0, tfar], u weighting p1, v weighting p2.
bool hit_triangle(uint tri, vec3 o, vec3 d, float tfar, out float t, out float u, out float v) {
  const Triangle tr = tris[tri];
  const vec3 e1 = tr.p0 - tr.p1;
  const vec3 e2 = tr.p2 - tr.p0;
  const vec3 ng = glm_cross(e2, e1);
  const vec3 c = tr.p0 - o;
  const vec3 r = glm_cross(c, d);
  const float den = dot(ng, d);
  const float abs_den = abs(den);
  const float sgn = den < 0.0 ? -1.0 : 1.0;
  const float U = dot(r, e2) * sgn;
  const float V = dot(r, e1) * sgn;
  t = 0.0;
  u = 0.0;
  v = 0.0;
  if (den == 0.0 || U < 0.0 || V < 0.0 || U + V > abs_den) return false;
  const float T = dot(ng, c) * sgn;
  if (!(T > 0.0 && T <= abs_den * tfar)) return false;
  const float rcp_den = 1.0 / abs_den;
  t = T * rcp_den;
  u = U * rcp_den;
  v = V * rcp_den;
  return true;
}

// Slab test; tfar widened by 2 ulp-ish so boxes never cut off a hit on their faces.
bool hit_box(vec3 bmin, vec3 bmax, vec3 o, vec3 inv_d, float tmax, out float tnear) {
  const vec3 t0 = (bmin - o) * inv_d;
  const vec3 t1 = (bmax - o) * inv_d;
  const vec3 lo = min(t0, t1);
  const vec3 hi = max(t0, t1);
  tnear = max(max(lo.x, lo.y), max(lo.z, 0.0));
  const float tf = min(min(hi.x, hi.y), min(hi.z, tmax)) * 1.0000003;
  return tnear <= tf;
}

vec3 safe_inverse(vec3 d) {
  const float tiny = 1e-20;
  return 1.0 / vec3(abs(d.x) < tiny ? (d.x < 0.0 ? -tiny : tiny) : d.x,
                    abs(d.y) < tiny ? (d.y < 0.0 ? -tiny : tiny) : d.y,
                    abs(d.z) < tiny ? (d.z < 0.0 ? -tiny : tiny) : d.z);
}

// Closest hit for t in (0, tfar]; any_hit stops at the first (shadow rays).
bool traverse(vec3 o, vec3 d, float tfar, bool any_hit, out float hit_t, out float hit_u, out float hit_v,
              out uint hit_tri) {
  const vec3 inv_d = safe_inverse(d);
  uint stack[BVH_STACK];
  int sp = 0;
  uint ref = 0u;  // the root node
  bool found = false;
  hit_t = tfar;
  hit_u = 0.0;
  hit_v = 0.0;
  hit_tri = 0u;
  for (;;) {
    if ((ref & LEAF_BIT) != 0u) {
      const uint first = ref & 0x7FFFFFFu;
      const uint count = (ref >> 27u) & 15u;
      for (uint k = 0u; k < count; ++k) {
        const uint tri = prims[first + k];
        float t, u, v;
        if (!hit_triangle(tri, o, d, hit_t, t, u, v)) continue;
        if (tris[tri].masked != 0u && !alpha_passes(tri, u, v)) continue;
        found = true;
        hit_t = t;
        hit_u = u;
        hit_v = v;
        hit_tri = tri;
        if (any_hit) return true;
      }
    } else {
      const Node n = nodes[ref];
      float tl, tr;
      const bool hl = n.left != EMPTY_CHILD && hit_box(n.lmin, n.lmax, o, inv_d, hit_t, tl);
      const bool hr = n.right != EMPTY_CHILD && hit_box(n.rmin, n.rmax, o, inv_d, hit_t, tr);
      if (hl && hr) {
        const bool left_first = tl <= tr;
        if (sp < BVH_STACK) stack[sp++] = left_first ? n.right : n.left;
        ref = left_first ? n.left : n.right;
        continue;
      }
      if (hl) {
        ref = n.left;
        continue;
      }
      if (hr) {
        ref = n.right;
        continue;
      }
    }
    if (sp == 0) break;
    ref = stack[--sp];
  }
  return found;
}

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
    const bool hit = traverse(p.origin, p.dir, positive_infinity(), false, t, u, v, tri);
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
    if (FX_TEXTURES && m.texture >= 0) base *= sample_texture(m.texture, texcoord(tri, m.texcoord, u, v)).rgb;
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
        float st, su, sv;
        uint stri;
        if (!traverse(pos + n * epsilon, l, tfar, true, st, su, sv, stri)) color += contrib;
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

// ---- ray counters: summed per workgroup, one atomic per kind and group ------------

shared uint group_rays[4];

void begin_counting() {
  if (gl_LocalInvocationIndex < 4u) group_rays[gl_LocalInvocationIndex] = 0u;
  barrier();
}

void count_rays(uint primary, uvec3 secondary) {
  if (primary != 0u) atomicAdd(group_rays[0], primary);
  if (secondary.x != 0u) atomicAdd(group_rays[1], secondary.x);
  if (secondary.y != 0u) atomicAdd(group_rays[2], secondary.y);
  if (secondary.z != 0u) atomicAdd(group_rays[3], secondary.z);
}

void end_counting() {
  barrier();
  if (gl_LocalInvocationIndex < 4u && group_rays[gl_LocalInvocationIndex] != 0u)
    atomicAdd(counters[gl_LocalInvocationIndex], group_rays[gl_LocalInvocationIndex]);
}

#endif
