// The scene as the tracers read it per hit: the std430 structs and storage
// buffers of set 0 (samples/gpu_engine/src/scene_data.hpp declares the same),
// the textures (sampled images) and the alpha-mask test. Shared by the compute tracer
// (trace_core.glsl), the ray-tracing pipeline's any-hit shader and its hit
// shaders: no traversal and no shading here. Bindings 0 and 1 belong to the
// scene query (scene_bvh.glsl or scene_rt.glsl).
#ifndef FOVEART_GPU_SCENE_DATA_GLSL
#define FOVEART_GPU_SCENE_DATA_GLSL

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
  uint texture_flags;  // its texture's wrap_s | wrap_t << 2 | nearest << 4 | srgb8 << 5
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


layout(std430, set = 0, binding = 2) readonly buffer Triangles { Triangle tris[]; };
layout(std430, set = 0, binding = 3) readonly buffer Shadings { Shading shading[]; };
layout(std430, set = 0, binding = 4) readonly buffer Materials { Material materials[]; };
layout(std430, set = 0, binding = 5) readonly buffer Lights { Light lights[]; };
// The textures the materials sample (scene_textures.hpp): sampled images, RGBA8
// sRGB or float. Indexed with constants only (slot_texel): no descriptor
// indexing needed.
layout(constant_id = 3) const uint TEXTURE_COUNT = 32u;  // slots holding scene textures
layout(set = 0, binding = 6) uniform sampler2D scene_textures[32];  // kTextureSlots
layout(std430, set = 0, binding = 7) readonly buffer Globals {
  vec3 sky_zenith;
  float epsilon;
  vec3 sky_horizon;
  uint light_count;
  vec3 ambient;
  uint globals_pad;
};
// primary, shadow, reflection, refraction; then, with COUNT_WORK (the compute
// tracer only), BVH nodes visited and triangles tested, each as (low, high) words.
layout(std430, set = 0, binding = 8) buffer Counters { uint counters[8]; };
layout(constant_id = 4) const uint COUNT_WORK = 0u;  // GpuTracerOptions::count_work

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

// Slot `slot`'s texel p and size at a level, and its levels, through a switch of constant
// indices: slots past TEXTURE_COUNT are specialised away.
#define FOVEART_SLOT(k) \
  case k:               \
    if (uint(k) < TEXTURE_COUNT) return FOVEART_SLOT_OP(scene_textures[k]); \
    break;
#define FOVEART_SLOTS                                                                                  \
  switch (slot) {                                                                                      \
    FOVEART_SLOT(0) FOVEART_SLOT(1) FOVEART_SLOT(2) FOVEART_SLOT(3) FOVEART_SLOT(4) FOVEART_SLOT(5)     \
    FOVEART_SLOT(6) FOVEART_SLOT(7) FOVEART_SLOT(8) FOVEART_SLOT(9) FOVEART_SLOT(10) FOVEART_SLOT(11)   \
    FOVEART_SLOT(12) FOVEART_SLOT(13) FOVEART_SLOT(14) FOVEART_SLOT(15) FOVEART_SLOT(16) FOVEART_SLOT(17) \
    FOVEART_SLOT(18) FOVEART_SLOT(19) FOVEART_SLOT(20) FOVEART_SLOT(21) FOVEART_SLOT(22) FOVEART_SLOT(23) \
    FOVEART_SLOT(24) FOVEART_SLOT(25) FOVEART_SLOT(26) FOVEART_SLOT(27) FOVEART_SLOT(28) FOVEART_SLOT(29) \
    FOVEART_SLOT(30) FOVEART_SLOT(31)                                                                  \
    default: break;                                                                                    \
  }
#define FOVEART_SLOT_OP(t) texelFetch(t, p, level)
vec4 slot_texel(int slot, ivec2 p, int level) {
  FOVEART_SLOTS
  return vec4(1.0);
}
#undef FOVEART_SLOT_OP
#define FOVEART_SLOT_OP(t) textureSize(t, level)
ivec2 slot_size(int slot, int level) {
  FOVEART_SLOTS
  return ivec2(1);
}
#undef FOVEART_SLOT_OP
#define FOVEART_SLOT_OP(t) textureQueryLevels(t)
int slot_levels(int slot) {
  FOVEART_SLOTS
  return 1;
}
#undef FOVEART_SLOT_OP
#undef FOVEART_SLOTS
#undef FOVEART_SLOT

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

// foveation::srgb_to_linear per channel.
vec3 srgb_to_linear(vec3 c) {
  return mix(pow((c + 0.055) / 1.055, vec3(2.4)), c / 12.92, lessThanEqual(c, vec3(0.04045)));
}

// The texel as the CPU engine holds it: sRGB bytes (flags & 32) decoded here,
// in float, as the loader decodes them.
vec4 texel_at(int slot, int level, ivec2 size, uint flags, int xi, int yi) {
  vec4 t = slot_texel(slot, ivec2(wrap_texel(xi, size.x, flags & 3u), wrap_texel(yi, size.y, (flags >> 2u) & 3u)),
                      level);
  if ((flags & 32u) != 0u) t.rgb = srgb_to_linear(t.rgb);
  return t;
}

// sample_texture: bilinear (or nearest), uv origin top-left; flags: wrap_s |
// wrap_t << 2 | nearest << 4 | srgb8 << 5. Texels fetched, decoded, wrapped and
// filtered here in float as the CPU engine does (texture_sampler.hpp): lavapipe's
// own sRGB decode is up to 1.8 % off in dark texels, past the per-ray tolerance.
vec4 sample_texture_level(int slot, int level, uint flags, vec2 uv) {
  const ivec2 size = slot_size(slot, level);
  if (!finite(uv.x) || !finite(uv.y)) uv = vec2(0.0);
  uv = clamp(uv, vec2(-1.0e6), vec2(1.0e6));
  const float x = uv.x * float(size.x) - 0.5;
  const float y = uv.y * float(size.y) - 0.5;
  const float fx0 = floor(x);
  const float fy0 = floor(y);
  const int x0 = int(fx0);
  const int y0 = int(fy0);
  if ((flags & 16u) != 0u) return texel_at(slot, level, size, flags, int(floor(x + 0.5)), int(floor(y + 0.5)));
  const float ax = x - fx0;
  const float ay = y - fy0;
  return glm_mix4(glm_mix4(texel_at(slot, level, size, flags, x0, y0), texel_at(slot, level, size, flags, x0 + 1, y0), ax),
                  glm_mix4(texel_at(slot, level, size, flags, x0, y0 + 1),
                           texel_at(slot, level, size, flags, x0 + 1, y0 + 1), ax),
                  ay);
}

// Level 0, as the CPU engine samples.
vec4 sample_texture(int slot, uint flags, vec2 uv) { return sample_texture_level(slot, 0, flags, uv); }

// At level of detail `lod` (texture_mips.hpp's chain): level 0 for lod <= 0 (exactly
// sample_texture), else the two levels around it mixed (trilinear), the last level past the chain.
vec4 sample_texture_lod(int slot, uint flags, vec2 uv, float lod) {
  if (!(lod > 0.0)) return sample_texture(slot, flags, uv);
  const int last = slot_levels(slot) - 1;
  const float l = min(lod, float(last));
  const int l0 = int(floor(l));
  const int l1 = min(l0 + 1, last);
  const float a = l - float(l0);
  const vec4 c0 = sample_texture_level(slot, l0, flags, uv);
  return a > 0.0 ? glm_mix4(c0, sample_texture_level(slot, l1, flags, uv), a) : c0;
}

// Tracer::Impl::texcoord.
vec2 texcoord(uint tri, int set, float u, float v) {
  const Shading s = shading[tri];
  if (set == 0) return (1.0 - u - v) * s.uva.xy + u * s.uva.zw + v * s.uvb.xy;
  return (1.0 - u - v) * s.uvb.zw + u * s.uvc.xy + v * s.uvc.zw;
}

// The texture level of detail of a ray cone at a triangle hit: Akenine-Moller et al. 2019,
// "Texture Level of Detail Strategies for Real-Time Ray Tracing" (Ray Tracing Gems ch. 20),
// lambda = 0.5 log2(t_a / p_a) + log2(w / |n.d|), with t_a the triangle's area in texels,
// p_a in square metres and w the cone's width at the hit, 2 t tan(footprint_rad).
float cone_texture_lod(uint tri, int set, int slot, float t, float footprint_rad, float cos_view) {
  const Triangle tr = tris[tri];
  const float world_area = length(glm_cross(tr.p1 - tr.p0, tr.p2 - tr.p0));
  const vec2 uv0 = texcoord(tri, set, 0.0, 0.0), uv1 = texcoord(tri, set, 1.0, 0.0), uv2 = texcoord(tri, set, 0.0, 1.0);
  const vec2 size = vec2(slot_size(slot, 0));
  const vec2 e1 = (uv1 - uv0) * size, e2 = (uv2 - uv0) * size;
  const float texel_area = abs(e1.x * e2.y - e1.y * e2.x);
  const float width_m = 2.0 * t * tan(footprint_rad);
  if (!(world_area > 0.0) || !(texel_area > 0.0) || !(width_m > 0.0)) return 0.0;
  return 0.5 * log2(texel_area / world_area) + log2(width_m / max(abs(cos_view), 1e-3));
}

// Tracer::Impl::alpha_passes (glTF alphaMode MASK).
bool alpha_passes(uint tri, float u, float v) {
  const Material m = materials[tris[tri].material];
  float alpha = m.base_color.a;
  if (m.texture >= 0) alpha *= sample_texture(m.texture, m.texture_flags, texcoord(tri, m.texcoord, u, v)).a;
  return alpha >= m.alpha_cutoff;
}

#endif
