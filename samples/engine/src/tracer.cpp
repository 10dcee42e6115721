// Embree scene lifecycle (error callback -> device -> scene -> commit -> trace ->
// release, as in Embree's minimal tutorial) and the packet kernels. One kernel
// is compiled per effect combination; an absent effect has no code in it.
#include <engine/tracer.hpp>

#include <foveation/ray_batch_reader.hpp>

#include "shading.hpp"
#include "texture_sampler.hpp"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <mutex>
#include <new>
#include <utility>

namespace foveart::engine {
namespace {

constexpr int kLanes = 16;
constexpr uint32_t kMxcsrFtzDaz = 0x8040;  // flush-to-zero | denormals-are-zero

// Sets FTZ/DAZ on the calling (tracing) thread for the scope, as Embree asks,
// and restores the caller's floating-point mode afterwards.
class ScopedFlushDenormals {
 public:
  ScopedFlushDenormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kMxcsrFtzDaz); }
  ~ScopedFlushDenormals() { _mm_setcsr(saved_); }
  ScopedFlushDenormals(const ScopedFlushDenormals&) = delete;
  ScopedFlushDenormals& operator=(const ScopedFlushDenormals&) = delete;

 private:
  unsigned int saved_;
};

// Per-batch counters, folded into the tracer's atomics once per batch.
struct LocalCounts {
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  uint64_t packets = 0;
};

// Rays of one packet: what to trace and where its radiance goes.
struct PacketIn {
  alignas(64) int valid[kLanes];
  glm::vec3 origin[kLanes];
  glm::vec3 dir[kLanes];
  glm::vec3 weight[kLanes];
  uint32_t target[kLanes];
  float* primary_depth_m = nullptr;  // primary packets: per target, the hit distance (+inf: sky)
};

// Surface data of a packet's lanes that hit.
struct PacketHits {
  bool hit[kLanes] = {};
  glm::vec3 pos[kLanes], nrm[kLanes], base[kLanes];
  const Material* mat[kLanes] = {};
  float cos_view[kLanes] = {};
  bool front[kLanes] = {};
};

// Lane i of a 16-wide packet: the ray origin + t dir, t in [0, tfar].
template <typename RayPacket>
[[gnu::always_inline]] inline void set_lane(RayPacket& ray, int i, glm::vec3 origin, glm::vec3 dir, float tfar) {
  ray.org_x[i] = origin.x;
  ray.org_y[i] = origin.y;
  ray.org_z[i] = origin.z;
  ray.dir_x[i] = dir.x;
  ray.dir_y[i] = dir.y;
  ray.dir_z[i] = dir.z;
  ray.tnear[i] = 0.0f;
  ray.tfar[i] = tfar;
  ray.time[i] = 0.0f;
  ray.mask[i] = 0xFFFFFFFFu;
  ray.id[i] = static_cast<unsigned int>(i);
  ray.flags[i] = 0;
}

// An inactive lane. On a CPU without AVX-512, Embree runs
// rtcIntersect16/rtcOccluded16 through its ray-stream filter, which ignores
// the valid mask and skips only rays with tnear > tfar (Embree 3 API,
// "rtcIntersect4/8/16" and "RTCRay"); a lane left uninitialised is then
// traced, and a NaN in it trips Embree's ray.valid() assertion. So every
// inactive lane holds a finite ray that both conventions skip.
template <typename RayPacket>
[[gnu::always_inline]] inline void set_inactive_lane(RayPacket& ray, int i) {
  set_lane(ray, i, glm::vec3(0.0f), glm::vec3(0.0f, 0.0f, 1.0f), -std::numeric_limits<float>::infinity());
}

void embree_error(void* user, RTCError code, const char* message) {
  (void)user;
  std::fprintf(stderr, "foveart engine: Embree error %d: %s\n", static_cast<int>(code),
               message ? message : "(no message)");
}

}  // namespace

struct Tracer::Impl {
  Scene scene;
  TracerOptions options;
  Effects scene_effects;
  Effects effects;
  RTCDevice device = nullptr;
  RTCScene rtc_scene = nullptr;
  std::array<std::vector<uint32_t>, 2> prim_to_triangle;  // per geometry id
  std::vector<glm::vec3> face_normal;
  float epsilon = 1e-4f;
  std::atomic<uint64_t> n_primary{0}, n_shadow{0}, n_reflection{0}, n_refraction{0}, n_packets{0};
  using Kernel = void (Impl::*)(PacketIn&, int, glm::vec3*, LocalCounts&) const;
  Kernel kernel = nullptr;

  ~Impl() {
    // Release in reverse order of creation; Embree reference-counts both.
    if (rtc_scene) rtcReleaseScene(rtc_scene);
    if (device) rtcReleaseDevice(device);
  }

  bool build(std::string* error);
  void add_geometry(const std::vector<uint32_t>& tris, unsigned int id, bool masked);
  static void alpha_filter(const RTCFilterFunctionNArguments* args);
  bool alpha_passes(uint32_t triangle, float u, float v) const;

  glm::vec2 texcoord(uint32_t tri, int set, float u, float v) const {
    const std::vector<glm::vec2>& uvs = set == 0 ? scene.mesh.uv0 : scene.mesh.uv1;
    if (uvs.empty()) return glm::vec2(0.0f);
    const glm::uvec3 t = scene.mesh.triangles[tri];
    return (1.0f - u - v) * uvs[t.x] + u * uvs[t.y] + v * uvs[t.z];
  }

  template <uint32_t kFx>
  void trace_packet(PacketIn& in, int depth, glm::vec3* color, LocalCounts& counts) const;
  // The steps of trace_packet, inlined into each kernel; add_direct_light is
  // one call per packet (inlined, it cost the kernel ~7 % more instructions).
  [[gnu::always_inline]] inline void intersect(const PacketIn& in, RTCIntersectContext& ctx, RTCRayHit16& rh) const;
  template <bool kTextures>
  [[gnu::always_inline]] inline void shade_hits(PacketIn& in, const RTCRayHit16& rh, PacketHits& hits,
                                                glm::vec3* color) const;
  void add_direct_light(const PacketIn& in, const PacketHits& hits, RTCIntersectContext& ctx, glm::vec3* color,
                        LocalCounts& counts) const;
  [[gnu::always_inline]] inline int reflection_packet(const PacketIn& in, const PacketHits& hits, PacketIn& next) const;
  template <bool kReflection>
  [[gnu::always_inline]] inline int refraction_packet(const PacketIn& in, const PacketHits& hits, PacketIn& next) const;

  int32_t trace(const FoveartRayBatch* batch) noexcept;
};

namespace {

template <uint32_t... I>
constexpr std::array<Tracer::Impl::Kernel, sizeof...(I)> make_kernels(std::integer_sequence<uint32_t, I...>) {
  return {&Tracer::Impl::trace_packet<I>...};
}

}  // namespace

bool Tracer::Impl::alpha_passes(uint32_t triangle, float u, float v) const {
  const Material& m = scene.materials[scene.mesh.triangle_material[triangle]];
  float alpha = m.base_color.a;
  if (m.base_color_texture >= 0)
    alpha *= sample_texture(scene.textures[static_cast<size_t>(m.base_color_texture)],
                            texcoord(triangle, m.base_color_texcoord, u, v)).a;
  return alpha >= m.alpha_cutoff;
}

// Alpha-mask test for both intersection and occlusion rays (glTF alphaMode MASK).
void Tracer::Impl::alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* self = static_cast<const Impl*>(args->geometryUserPtr);
  for (unsigned int i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t prim = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i);
    const float v = RTCHitN_v(args->hit, args->N, i);
    if (!self->alpha_passes(self->prim_to_triangle[1][prim], u, v)) args->valid[i] = 0;
  }
}

void Tracer::Impl::add_geometry(const std::vector<uint32_t>& tris, unsigned int id, bool masked) {
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const std::vector<glm::vec3>& pos = scene.mesh.positions;
  // Embree-allocated buffers are padded as Embree needs (16-byte reads at the end).
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), pos.size()));
  auto* ix = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                            3 * sizeof(uint32_t), tris.size()));
  if (v && ix) {
    for (size_t i = 0; i < pos.size(); ++i) {
      v[3 * i] = pos[i].x;
      v[3 * i + 1] = pos[i].y;
      v[3 * i + 2] = pos[i].z;
    }
    for (size_t i = 0; i < tris.size(); ++i) {
      const glm::uvec3 t = scene.mesh.triangles[tris[i]];
      ix[3 * i] = t.x;
      ix[3 * i + 1] = t.y;
      ix[3 * i + 2] = t.z;
    }
  }
  if (masked) {
    rtcSetGeometryUserData(geom, this);
    rtcSetGeometryIntersectFilterFunction(geom, &Impl::alpha_filter);
    rtcSetGeometryOccludedFilterFunction(geom, &Impl::alpha_filter);
  }
  rtcCommitGeometry(geom);            // geometry must be committed before the scene
  rtcAttachGeometryByID(rtc_scene, geom, id);
  rtcReleaseGeometry(geom);           // the scene holds the reference from now on
}

bool Tracer::Impl::build(std::string* error) {
  if (!prepare_scene(scene, error)) return false;
  const Mesh& m = scene.mesh;
  scene_effects = derive_effects(scene);
  effects = scene_effects & options.allowed;
  static constexpr auto kKernels = make_kernels(std::make_integer_sequence<uint32_t, 16>{});
  kernel = kKernels[options.generic_kernel ? options.allowed.bits() : effects.bits()];

  face_normal.resize(m.triangles.size());
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const glm::uvec3 t = m.triangles[i];
    face_normal[i] = glm::normalize(glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]));
  }
  const Bounds b = scene_bounds(m);
  epsilon = 1e-4f * std::max(1.0f, glm::length(b.max - b.min));

  device = rtcNewDevice(options.embree_config.empty() ? nullptr : options.embree_config.c_str());
  if (!device) {
    if (error) *error = "Embree device creation failed (error " + std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")";
    return false;
  }
  rtcSetDeviceErrorFunction(device, &embree_error, nullptr);
  rtc_scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(rtc_scene, RTC_BUILD_QUALITY_HIGH);

  // Alpha-masked triangles with a texture go to their own geometry with a filter;
  // a masked material without texture is all-or-nothing and decided here.
  std::vector<uint32_t> opaque, masked;
  for (uint32_t i = 0; i < m.triangles.size(); ++i) {
    const Material& mat = scene.materials[m.triangle_material[i]];
    if (mat.alpha_mode == AlphaMode::kMask) {
      if (mat.base_color_texture >= 0) masked.push_back(i);
      else if (mat.base_color.a >= mat.alpha_cutoff) opaque.push_back(i);
    } else {
      opaque.push_back(i);
    }
  }
  if (!opaque.empty()) add_geometry(opaque, 0, false);
  if (!masked.empty()) add_geometry(masked, 1, true);
  prim_to_triangle[0] = std::move(opaque);
  prim_to_triangle[1] = std::move(masked);
  rtcCommitScene(rtc_scene);  // builds the BVH; the scene is read-only (thread-safe) from here
  const RTCError err = rtcGetDeviceError(device);
  if (err != RTC_ERROR_NONE) {
    if (error) *error = "Embree scene build failed (error " + std::to_string(static_cast<int>(err)) + ")";
    return false;
  }
  return true;
}

template <uint32_t kFx>
void Tracer::Impl::trace_packet(PacketIn& in, int depth, glm::vec3* color, LocalCounts& counts) const {
  constexpr bool kShadows = (kFx & 1u) != 0;
  constexpr bool kReflection = (kFx & 2u) != 0;
  constexpr bool kRefraction = (kFx & 4u) != 0;
  constexpr bool kTextures = (kFx & 8u) != 0;

  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  // Every packet is coherent by construction: camera rays of neighbouring pixels
  // or points (screen rows, the point set's Hilbert order), then the shadow rays
  // of their hits towards one light and their mirror bounces. Embree's coherent
  // traversal (rtcInitIntersectContext(3)) traces them faster than its default
  // for incoherent rays (engine_bench BM_Full/BM_Foveated, docs/results/engine_traversal.md).
  ctx.flags = options.incoherent_traversal ? RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT : RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRayHit16 rh;
  intersect(in, ctx, rh);
  ++counts.packets;
  PacketHits hits;
  shade_hits<kTextures>(in, rh, hits, color);
  if constexpr (kShadows) add_direct_light(in, hits, ctx, color, counts);
  if (depth >= options.max_depth) return;

  if constexpr (kReflection) {
    PacketIn next;
    if (const int n_valid = reflection_packet(in, hits, next); n_valid > 0) {
      counts.reflection += static_cast<uint64_t>(n_valid);
      trace_packet<kFx>(next, depth + 1, color, counts);
    }
  }
  if constexpr (kRefraction) {
    PacketIn next;
    if (const int n_valid = refraction_packet<kReflection>(in, hits, next); n_valid > 0) {
      counts.refraction += static_cast<uint64_t>(n_valid);
      trace_packet<kFx>(next, depth + 1, color, counts);
    }
  }
}

// The packet's active lanes traced; every other lane a finite ray Embree skips.
void Tracer::Impl::intersect(const PacketIn& in, RTCIntersectContext& ctx, RTCRayHit16& rh) const {
  for (int i = 0; i < kLanes; ++i) {
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    if (in.valid[i] == -1) {
      set_lane(rh.ray, i, in.origin[i], in.dir[i], std::numeric_limits<float>::infinity());
    } else {
      set_inactive_lane(rh.ray, i);
    }
  }
  rtcIntersect16(in.valid, rtc_scene, &ctx, &rh);
}

// Sky for the lanes that missed, emission and ambient for those that hit, and
// their surface data into `hits`; primary packets also record each hit's distance.
template <bool kTextures>
void Tracer::Impl::shade_hits(PacketIn& in, const RTCRayHit16& rh, PacketHits& hits, glm::vec3* color) const {
  for (int i = 0; i < kLanes; ++i) {
    if (in.valid[i] != -1) continue;
    if (in.primary_depth_m != nullptr) {
      in.primary_depth_m[in.target[i]] =
          rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID ? std::numeric_limits<float>::infinity() : rh.ray.tfar[i];
    }
    if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) {
      color[in.target[i]] += in.weight[i] * sky_radiance(scene, in.dir[i]);
      continue;
    }
    hits.hit[i] = true;
    const uint32_t tri = prim_to_triangle[rh.hit.geomID[i] & 1u][rh.hit.primID[i]];
    const float u = rh.hit.u[i];
    const float v = rh.hit.v[i];
    const glm::uvec3 t = scene.mesh.triangles[tri];
    const Material& m = scene.materials[scene.mesh.triangle_material[tri]];
    hits.mat[i] = &m;
    hits.pos[i] = in.origin[i] + rh.ray.tfar[i] * in.dir[i];
    glm::vec3 n = (1.0f - u - v) * scene.mesh.normals[t.x] + u * scene.mesh.normals[t.y] + v * scene.mesh.normals[t.z];
    const float len2 = glm::dot(n, n);
    n = len2 > 1e-12f ? n * (1.0f / std::sqrt(len2)) : face_normal[tri];
    hits.front[i] = glm::dot(in.dir[i], n) < 0.0f;  // entering the surface (for refraction)
    if (!hits.front[i]) n = -n;                     // shade the side the ray sees
    hits.nrm[i] = n;
    hits.cos_view[i] = -glm::dot(in.dir[i], n);
    glm::vec3 c(m.base_color);
    if constexpr (kTextures) {
      if (m.base_color_texture >= 0)
        c *= glm::vec3(sample_texture(scene.textures[static_cast<size_t>(m.base_color_texture)],
                                      texcoord(tri, m.base_color_texcoord, u, v)));
    }
    hits.base[i] = c;
    // Ambient with a view-facing falloff: shape cues for unlit scenes, no rays needed.
    const float ambient_shape = 0.4f + 0.6f * hits.cos_view[i];
    color[in.target[i]] += in.weight[i] * (m.emissive + c * (diffuse_weight(m) * ambient_shape) * scene.ambient);
  }
}

// Each light's diffuse contribution to the hits it reaches: a packet of shadow rays per light.
void Tracer::Impl::add_direct_light(const PacketIn& in, const PacketHits& hits, RTCIntersectContext& ctx,
                                    glm::vec3* color, LocalCounts& counts) const {
  for (const Light& light : scene.lights) {
    alignas(64) int valid[kLanes];
    alignas(64) RTCRay16 sr;
    glm::vec3 contrib[kLanes];
    int n_valid = 0;
    for (int i = 0; i < kLanes; ++i) {
      valid[i] = 0;
      set_inactive_lane(sr, i);  // until the lane proves to need a shadow ray
      if (!hits.hit[i]) continue;
      const float kd = diffuse_weight(*hits.mat[i]);
      if (kd <= 0.0f) continue;
      glm::vec3 l;
      float dist = 0.0f;
      const glm::vec3 radiance = light_incident(light, hits.pos[i], &l, &dist);
      const float cos_l = glm::dot(hits.nrm[i], l);
      if (cos_l <= 0.0f || radiance == glm::vec3(0.0f)) continue;
      contrib[i] = in.weight[i] * hits.base[i] * (kd * kInvPi * cos_l) * radiance;
      // tfar never below tnear: a light closer than 2 epsilon is unoccluded on every ISA (a stream would skip it).
      set_lane(sr, i, hits.pos[i] + hits.nrm[i] * epsilon, l,
               std::isinf(dist) ? dist : std::max(dist - 2.0f * epsilon, 0.0f));
      valid[i] = -1;
      ++n_valid;
    }
    if (n_valid == 0) continue;
    counts.shadow += static_cast<uint64_t>(n_valid);
    rtcOccluded16(valid, rtc_scene, &ctx, &sr);
    ++counts.packets;
    for (int i = 0; i < kLanes; ++i)  // Embree sets tfar to -inf for occluded rays
      if (valid[i] == -1 && sr.tfar[i] >= 0.0f) color[in.target[i]] += contrib[i];
  }
}

// The mirror bounces of the reflective hits worth tracing, into `next`; how many.
int Tracer::Impl::reflection_packet(const PacketIn& in, const PacketHits& hits, PacketIn& next) const {
  int n_valid = 0;
  for (int i = 0; i < kLanes; ++i) {
    next.valid[i] = 0;
    if (!hits.hit[i] || !hits.mat[i]->reflective()) continue;
    const glm::vec3 w = in.weight[i] * reflection_weight(*hits.mat[i], hits.base[i], hits.cos_view[i]);
    if (std::max(w.x, std::max(w.y, w.z)) < 1e-3f) continue;
    next.valid[i] = -1;
    next.origin[i] = hits.pos[i] + hits.nrm[i] * epsilon;
    next.dir[i] = glm::reflect(in.dir[i], hits.nrm[i]);
    next.weight[i] = w;
    next.target[i] = in.target[i];
    ++n_valid;
  }
  return n_valid;
}

// The rays through the transmissive hits worth tracing, into `next`: Snell
// refraction, or straight on through alpha blending; how many.
template <bool kReflection>
int Tracer::Impl::refraction_packet(const PacketIn& in, const PacketHits& hits, PacketIn& next) const {
  int n_valid = 0;
  for (int i = 0; i < kLanes; ++i) {
    next.valid[i] = 0;
    if (!hits.hit[i] || !hits.mat[i]->transmissive()) continue;
    const Material& m = *hits.mat[i];
    const glm::vec3 pos = hits.pos[i], nrm = hits.nrm[i];
    glm::vec3 w(0.0f);
    glm::vec3 dir = in.dir[i];
    glm::vec3 origin = pos + in.dir[i] * epsilon;
    if (m.transmission > 0.0f) {
      // Snell refraction; without the reflection effect the Fresnel split is dropped.
      const float eta = hits.front[i] ? 1.0f / m.ior : m.ior;
      glm::vec3 t = glm::refract(in.dir[i], nrm, eta);
      if (glm::dot(t, t) == 0.0f) t = glm::reflect(in.dir[i], nrm);  // total internal reflection
      dir = glm::normalize(t);
      origin = pos + (glm::dot(dir, nrm) < 0.0f ? -nrm : nrm) * epsilon;
      glm::vec3 kt = hits.base[i] * m.transmission;
      if constexpr (kReflection) kt *= glm::vec3(1.0f) - reflection_weight(m, hits.base[i], hits.cos_view[i]);
      w = in.weight[i] * kt;
    } else {  // alpha blending: the ray continues straight through
      w = in.weight[i] * (1.0f - m.base_color.a);
    }
    if (std::max(w.x, std::max(w.y, w.z)) < 1e-3f) continue;
    next.valid[i] = -1;
    next.origin[i] = origin;
    next.dir[i] = dir;
    next.weight[i] = w;
    next.target[i] = in.target[i];
    ++n_valid;
  }
  return n_valid;
}

int32_t Tracer::Impl::trace(const FoveartRayBatch* batch) noexcept {
  ScopedFlushDenormals ftz;
  foveation::RayBatchReader batch_rays;
  if (const int32_t r = foveation::RayBatchReader::read(batch, &batch_rays);
      r != FOVEART_RESULT_SUCCESS || batch_rays.size() == 0)
    return r;
  try {
    LocalCounts counts;
    constexpr uint32_t kChunk = kLanes;
    glm::vec3 color[kChunk];
    float depth_m[kChunk];
    // The depth per ray (TAA reprojection) when the batch has room for it.
    float* out_depth = batch_rays.out_depth_m();
    PacketIn in;
    in.primary_depth_m = out_depth != nullptr ? depth_m : nullptr;
    for (uint32_t first = 0; first < batch->ray_count; first += kChunk) {
      const uint32_t n = std::min(kChunk, batch->ray_count - first);
      for (uint32_t i = 0; i < kChunk; ++i) {
        color[i] = glm::vec3(0.0f);
        depth_m[i] = std::numeric_limits<float>::quiet_NaN();  // a ray not traced gives no depth
        in.valid[i] = 0;
        if (i >= n) continue;
        if (!batch_rays.ray(first + i, &in.origin[i], &in.dir[i])) continue;  // black
        in.valid[i] = -1;
        in.weight[i] = glm::vec3(1.0f);
        in.target[i] = i;
      }
      (this->*kernel)(in, 0, color, counts);
      for (uint32_t i = 0; i < n; ++i) {
        glm::vec3 c = color[i];
        if (!std::isfinite(c.x + c.y + c.z)) c = glm::vec3(0.0f);
        float* out = batch->out_rgb + 3 * static_cast<size_t>(first + i);
        out[0] = std::max(c.x, 0.0f);
        out[1] = std::max(c.y, 0.0f);
        out[2] = std::max(c.z, 0.0f);
        if (out_depth != nullptr) out_depth[first + i] = depth_m[i];
      }
    }
    n_primary.fetch_add(batch->ray_count, std::memory_order_relaxed);
    n_shadow.fetch_add(counts.shadow, std::memory_order_relaxed);
    n_reflection.fetch_add(counts.reflection, std::memory_order_relaxed);
    n_refraction.fetch_add(counts.refraction, std::memory_order_relaxed);
    n_packets.fetch_add(counts.packets, std::memory_order_relaxed);
    return FOVEART_RESULT_SUCCESS;
  } catch (const std::bad_alloc&) {
    return FOVEART_RESULT_ERROR_OUT_OF_MEMORY;
  } catch (...) {
    return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  }
}

// ---- Tracer ------------------------------------------------------------------------------

Tracer::Tracer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Tracer::~Tracer() = default;

std::unique_ptr<Tracer> Tracer::create(Scene scene, const TracerOptions& options, std::string* error) {
  try {
    auto impl = std::make_unique<Impl>();
    impl->scene = std::move(scene);
    impl->options = options;
    if (!impl->build(error)) return nullptr;
    return std::unique_ptr<Tracer>(new Tracer(std::move(impl)));
  } catch (const std::exception& e) {
    if (error) *error = std::string("engine: ") + e.what();
    return nullptr;
  }
}

int32_t Tracer::trace(const FoveartRayBatch* batch) noexcept { return impl_->trace(batch); }

HitRecord Tracer::intersect(glm::vec3 origin, glm::vec3 direction) const {
  ScopedFlushDenormals ftz;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = origin.x;
  rh.ray.org_y = origin.y;
  rh.ray.org_z = origin.z;
  rh.ray.dir_x = direction.x;
  rh.ray.dir_y = direction.y;
  rh.ray.dir_z = direction.z;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->rtc_scene, &ctx, &rh);
  HitRecord out;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
  out.hit = true;
  out.t = rh.ray.tfar;
  out.triangle = impl_->prim_to_triangle[rh.hit.geomID & 1u][rh.hit.primID];
  out.normal = impl_->face_normal[out.triangle];
  out.uv = impl_->texcoord(out.triangle, 0, rh.hit.u, rh.hit.v);
  return out;
}

const Scene& Tracer::scene() const { return impl_->scene; }
Effects Tracer::scene_effects() const { return impl_->scene_effects; }
Effects Tracer::effects() const { return impl_->effects; }

RayCounts Tracer::counts() const {
  RayCounts c;
  c.primary = impl_->n_primary.load(std::memory_order_relaxed);
  c.shadow = impl_->n_shadow.load(std::memory_order_relaxed);
  c.reflection = impl_->n_reflection.load(std::memory_order_relaxed);
  c.refraction = impl_->n_refraction.load(std::memory_order_relaxed);
  c.packets = impl_->n_packets.load(std::memory_order_relaxed);
  return c;
}

void Tracer::reset_counts() {
  impl_->n_primary = 0;
  impl_->n_shadow = 0;
  impl_->n_reflection = 0;
  impl_->n_refraction = 0;
  impl_->n_packets = 0;
}

}  // namespace foveart::engine

extern "C" int32_t foveart_engine_trace_rays(void* user_data, const FoveartRayBatch* batch) {
  if (!user_data) return FOVEART_RESULT_ERROR_INVALID_ARGUMENT;
  return static_cast<foveart::engine::Tracer*>(user_data)->trace(batch);
}
