// The sample engine's answer to "what colour do these rays see?": an Embree 3
// scene built from an engine Scene, traced Whitted-style in packets of 16.
//
// Lifetime:  create() builds and commits the Embree scene; the Tracer owns the
//            Scene and the Embree device; destroying it releases both.
// Threads:   trace() and the C callback may be called from any number of
//            threads at once (disjoint batches); counters are atomic.
// Effects:   the effect set (effects.hpp) is derived from the scene at create();
//            trace() runs the kernel compiled for exactly that set.
// Errors:    create() returns null and sets *error; trace() returns a
//            FoveartResult and never throws.
#pragma once

#include <engine/effects.hpp>
#include <engine/scene.hpp>

#include <foveation/ray_trace.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <memory>
#include <string>

namespace foveart::engine {

struct TracerOptions {
  int max_depth = 4;                 // secondary bounces (reflection/refraction) per path
  Effects allowed = Effects::all();  // effects to simulate at most (e.g. none() = primary-only)
  bool generic_kernel = false;       // benchmark only: run the all-effects kernel with
                                     // run-time checks instead of the specialised one
  bool incoherent_traversal = false; // benchmark only: Embree's traversal for incoherent
                                     // rays instead of its coherent one
  std::string embree_config;         // rtcNewDevice configuration string, e.g. "threads=1"
};

struct RayCounts {
  uint64_t primary = 0;
  uint64_t shadow = 0;
  uint64_t reflection = 0;
  uint64_t refraction = 0;
  // Embree calls (rtcIntersect16 + rtcOccluded16): total() / packets is the mean
  // number of active lanes of 16, a load-independent measure of packet coherence.
  uint64_t packets = 0;
  uint64_t total() const { return primary + shadow + reflection + refraction; }
};

// The rays traced between two readings of Tracer::counts(): later - earlier.
inline RayCounts operator-(const RayCounts& later, const RayCounts& earlier) {
  return RayCounts{later.primary - earlier.primary, later.shadow - earlier.shadow,
                   later.reflection - earlier.reflection, later.refraction - earlier.refraction,
                   later.packets - earlier.packets};
}

// One ray against the scene, for tests and tools.
struct HitRecord {
  bool hit = false;
  float t = 0.0f;
  glm::vec3 normal{0.0f};  // unit geometric normal, counter-clockwise front face
  glm::vec2 uv{0.0f};      // TEXCOORD_0 at the hit (0 when the mesh has none)
  uint32_t triangle = 0;   // index into Scene::mesh.triangles
};

class Tracer {
 public:
  static std::unique_ptr<Tracer> create(Scene scene, const TracerOptions& options = {},
                                        std::string* error = nullptr);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  // Traces one batch (see ray_trace.h). Rays come from origins_m/directions or,
  // when those are null, from view + sample_px. Thread-safe.
  int32_t trace(const FoveartRayBatch* batch) noexcept;

  HitRecord intersect(glm::vec3 origin, glm::vec3 direction) const;

  const Scene& scene() const;
  Effects scene_effects() const;  // what the scene calls for
  Effects effects() const;        // what the kernel simulates (scene & allowed)
  RayCounts counts() const;
  void reset_counts();

  struct Impl;

 private:
  explicit Tracer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace foveart::engine

extern "C" {
// The FoveartTraceRaysFn of the sample engine; user_data is a foveart::engine::Tracer*.
int32_t foveart_engine_trace_rays(void* user_data, const FoveartRayBatch* batch);
}
