#include "ray_batch.hpp"

#include <algorithm>
#include <cstring>

namespace foveart::layer {

bool same_view(const RayBatchView& a, const RayBatchView& b) {
  // Bit for bit: the app hands the layer the same xrLocateViews result twice.
  return std::memcmp(&a.pose, &b.pose, sizeof a.pose) == 0 && std::memcmp(&a.fov, &b.fov, sizeof a.fov) == 0 &&
         a.size_px.width == b.size_px.width && a.size_px.height == b.size_px.height;
}

XrResult RayBatches::acquire(std::int64_t now_ns, std::vector<RayBatchView> views, std::uint64_t* out_id,
                             std::uint64_t* out_rays_ready_value, std::uint64_t* out_traced_value) {
  if (out_) return XR_ERROR_CALL_ORDER_INVALID;
  TakenRayBatch batch;
  batch.id = next_id_++;
  batch.acquired_ns = now_ns;
  batch.views = std::move(views);
  *out_rays_ready_value = ++next_value_;
  batch.traced_value = ++next_value_;
  *out_traced_value = batch.traced_value;
  *out_id = batch.id;
  out_ = std::move(batch);
  ++acquired_;
  return XR_SUCCESS;
}

void RayBatches::withdraw() {
  if (!out_) return;
  // Nothing was signalled or promised: the values are handed out again, so that
  // each rays submission may wait for the value before its own (renderer).
  next_value_ -= 2;
  --acquired_;
  out_.reset();
}

XrResult RayBatches::release(std::uint64_t id) {
  if (out_ && out_->id == id) {
    if (!out_->released) {
      out_->released = true;
      return XR_SUCCESS;
    }
    // Two releases promise two signals of one value: neither can be relied on.
    out_->released_twice = true;
  }
  ++rejected_;
  if (std::find(retired_ids_.begin(), retired_ids_.end(), id) != retired_ids_.end()) return XR_ERROR_CALL_ORDER_INVALID;
  return XR_ERROR_VALIDATION_FAILURE;  // never handed out (0, future), or released already
}

std::optional<TakenRayBatch> RayBatches::take() {
  std::optional<TakenRayBatch> taken = std::move(out_);
  out_.reset();
  if (!taken || (taken->released && !taken->released_twice)) return taken;
  taken->released = false;
  ++retired_count_;
  retired_ids_.push_back(taken->id);
  if (retired_ids_.size() > kRetiredRemembered) retired_ids_.pop_front();
  ++generation_;    // the app may signal the old semaphore late: later batches use a new one
  next_value_ = 0;  // whose values start again
  return taken;
}

}  // namespace foveart::layer
