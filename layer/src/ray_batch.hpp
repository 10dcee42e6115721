// The app-recorded trace's bookkeeping (the extension header's "app-recorded
// trace"): which frame's ray batch is out, what the app promised, and the
// timeline values it waits for and signals. No Vulkan here: the renderer
// makes the rays and submits; this says whether a call is allowed and what
// xrEndFrame may wait for.
//
// One batch per frame: acquire -> (release) -> xrEndFrame takes it. Taken
// unreleased, it is retired: its views fall back, nobody waits for its
// tracedValue, and the semaphore's generation changes (the renderer hands out
// a new semaphore, since the app may still signal the old one late).
//
// Threads: not thread-safe; the renderer calls it under its frame lock.
#pragma once

#include <openxr/openxr.h>

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

namespace foveart::layer {

// What a view was acquired for; xrEndFrame's view must be the same, bit for bit.
struct RayBatchView {
  XrPosef pose{};
  XrFovf fov{};
  XrExtent2Di size_px{};
};
bool same_view(const RayBatchView& a, const RayBatchView& b);

// A frame's batch as xrEndFrame takes it.
struct TakenRayBatch {
  std::uint64_t id = 0;
  bool released = false;           // false: retired, its views fall back
  bool released_twice = false;     // released, then released again: retired as well (its promise is in doubt)
  std::uint64_t traced_value = 0;  // wait for it (released only)
  std::int64_t acquired_ns = 0;    // steady clock at acquire
  std::vector<RayBatchView> views;
};

class RayBatches {
 public:
  // The values of the next acquire: a new batch id and the timeline values on
  // the current semaphore. XR_ERROR_CALL_ORDER_INVALID while a batch is out
  // (acquired, not yet taken by xrEndFrame).
  XrResult acquire(std::int64_t now_ns, std::vector<RayBatchView> views, std::uint64_t* out_id,
                   std::uint64_t* out_rays_ready_value, std::uint64_t* out_traced_value);
  // The acquire could not submit its rays: the batch is withdrawn, as if never
  // made (its id stays used). Values on a semaphore are consecutive: each
  // batch's raysReadyValue is the previous batch's tracedValue + 1.
  void withdraw();
  // XR_SUCCESS; XR_ERROR_VALIDATION_FAILURE for an id never handed out or
  // released already (the batch out, released twice, is then retired at
  // xrEndFrame); XR_ERROR_CALL_ORDER_INVALID for a retired one.
  XrResult release(std::uint64_t id);
  // xrEndFrame: the frame's batch, if one was acquired; unreleased, it is retired.
  std::optional<TakenRayBatch> take();

  // Changes each time a batch is retired: the renderer's semaphore for that generation.
  std::uint64_t semaphore_generation() const { return generation_; }
  // Counts since creation.
  std::uint64_t acquired() const { return acquired_; }
  std::uint64_t retired() const { return retired_count_; }
  std::uint64_t rejected_releases() const { return rejected_; }

  // Retired ids remembered for the error of a late release (older ones read as "released already").
  static constexpr std::size_t kRetiredRemembered = 64;

 private:
  std::optional<TakenRayBatch> out_;  // acquired, not taken yet
  std::uint64_t next_id_ = 1;
  std::uint64_t next_value_ = 0;  // on the current generation's semaphore
  std::uint64_t generation_ = 0;
  std::deque<std::uint64_t> retired_ids_;
  std::uint64_t acquired_ = 0, retired_count_ = 0, rejected_ = 0;
};

}  // namespace foveart::layer
