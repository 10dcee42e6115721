#include "gpu/device_stages.hpp"

#include <stdexcept>
#include <utility>

#include "foveation/foveated_view.hpp"

namespace foveart::gpu {

DeviceFrame* device_frame(foveation::FrameResources& resources, const char* stage, std::string* error) {
  DeviceFrame* device = resources.device();
  if (device == nullptr)
    *error = std::string(stage) + " records on the device, and this frame's resources are the host's";
  return device;
}

VkCommandBuffer DeviceFrame::recording(const foveation::FrameContext& context, std::string* error) {
  if (begun) return cb;
  if (cb == VK_NULL_HANDLE && begin) cb = begin(*this, error);
  if (cb == VK_NULL_HANDLE) {
    if (error->empty()) *error = "GPU frame: no command buffer to record into";
    return VK_NULL_HANDLE;
  }
  if (eye == nullptr || tables == nullptr) {
    *error = "GPU frame: no eye or no tables on the device";
    return VK_NULL_HANDLE;
  }
  frame.tables = tables;
  frame.mapping = context.mapping;
  frame.view = context.view;
  frame.slot = slot;
  frame.srgb = srgb;
  frame.display = display;
  if (!eye->begin_frame(cb, frame, error)) return VK_NULL_HANDLE;
  begun = true;
  return cb;
}

// Stages 1-3 on the device: the engine's device trace into the frame slot's colours.
class DeviceTraceStage final : public foveation::TraceStage {
 public:
  DeviceTraceStage(std::shared_ptr<const foveation::ViewTables> tables, const foveation::ViewSettings& settings,
                   DeviceTraceEngine engine)
      : tables_(std::move(tables)), engine_(std::move(engine)) {
    device_.engine = [this](const DeviceRayBatch& batch) {
      const bool ok = engine_(batch);
      engine_failed_ = engine_failed_ || !ok;
      return ok;
    };
    device_.points = &tables_->points;
    device_.rays_per_point = std::uint32_t(settings.rays_per_point);
    device_.pixel_filter = settings.pixel_filter;
    device_.density = settings.content_density;
  }

  foveation::TraceStats trace(const foveation::FrameContext& frame, foveation::FrameResources& resources,
                              foveation::Executor& executor) override {
    foveation::TraceStats stats;
    DeviceFrame* d = device_frame(resources, "the device trace", &stats.error);
    if (d == nullptr) return stats;
    device_.view = frame.view;
    device_.mapping = frame.mapping;
    device_.frame_index = frame.frame_index;
    device_.sample_seed = frame.sample_seed;
    if (device_.density.enabled() && device_.levels == nullptr) device_.levels = &tables_->levels(executor);
    d->frame.device = &device_;
    engine_failed_ = false;
    const VkCommandBuffer cb = d->recording(frame, &stats.error);
    if (cb == VK_NULL_HANDLE || d->eye->record_trace(cb, d->frame, &stats.error)) return stats;
    if (engine_failed_) {  // the engine's failure, not the device's
      stats.failed_batches = 1;
      stats.error = "the engine's device trace returned an error";
    }
    return stats;
  }
  // No points on the host: the device made and resolved the rays.
  const foveation::TracedPoints& traced() const override { return nothing_; }

 private:
  std::shared_ptr<const foveation::ViewTables> tables_;
  DeviceTraceEngine engine_;
  DeviceTraceFrame device_;
  bool engine_failed_ = false;
  foveation::TracedPoints nothing_;
};

// Stages 1-3 through the engine's callback on the CPU, the traced colours uploaded into the frame slot.
class UploadedTrace final : public foveation::TraceStage {
 public:
  explicit UploadedTrace(std::unique_ptr<foveation::TraceStage> callback) : callback_(std::move(callback)) {}

  foveation::TraceStats trace(const foveation::FrameContext& frame, foveation::FrameResources& resources,
                              foveation::Executor& executor) override {
    std::string error;
    DeviceFrame* d = device_frame(resources, "the uploaded trace", &error);
    if (d == nullptr) {
      foveation::TraceStats stats;
      stats.error = error;
      return stats;
    }
    foveation::TraceStats stats = callback_->trace(frame, resources, executor);
    if (!stats.ok()) return stats;
    const foveation::TracedPoints& t = callback_->traced();
    d->frame.colors = &t.colors;
    d->frame.point_depth_m = &t.depth_m;
    d->frame.traced = t.runs;
    const VkCommandBuffer cb = d->recording(frame, &stats.error);
    if (cb == VK_NULL_HANDLE) return stats;
    d->uploaded = d->eye->upload_traced(d->frame, executor);
    (void)d->eye->record_trace(cb, d->frame, &stats.error);  // false: stats.error says why
    return stats;
  }
  const foveation::TracedPoints& traced() const override { return callback_->traced(); }

 private:
  std::unique_ptr<foveation::TraceStage> callback_;
};

// Stage 4: the colours scattered into their slots, every pixel gathered from them.
class DeviceGather final : public foveation::ReconstructStage {
 public:
  explicit DeviceGather(foveation::RbfClamp rbf_clamp) : rbf_clamp_(rbf_clamp) {}
  bool reconstruct(const foveation::FrameContext& frame, const foveation::TracedPoints&,
                   foveation::FrameResources& resources, foveation::Executor&, foveation::GatherStats*,
                   std::string* error) override {
    DeviceFrame* d = device_frame(resources, "the device's gather", error);
    const VkCommandBuffer cb = d != nullptr ? d->recording(frame, error) : VK_NULL_HANDLE;
    if (cb == VK_NULL_HANDLE) return false;
    d->frame.rbf_clamp = rbf_clamp_;
    d->eye->record_scatter(cb, d->frame, d->uploaded);
    d->eye->record_gather(cb, d->frame);
    return true;
  }

 private:
  foveation::RbfClamp rbf_clamp_;
};

// Stage 5: the host's history decides; the device applies the decision.
class DeviceHistory final : public foveation::TemporalHistory {
 public:
  explicit DeviceHistory(std::unique_ptr<foveation::TemporalHistory> host) : host_(std::move(host)) {}
  bool keeps_rays() const override { return host_->keeps_rays(); }
  void forget() override { host_->forget(); }
  foveation::TemporalFrame decide(const foveation::FrameContext& frame, const foveation::TracedPoints& traced,
                                  foveation::Executor& executor) override {
    return host_->decide(frame, traced, executor);
  }
  bool apply(const foveation::FrameContext& frame, const foveation::TracedPoints& traced,
             foveation::FrameResources& resources, foveation::Executor& executor, foveation::TemporalFrame* decision,
             std::string* error) override {
    DeviceFrame* d = device_frame(resources, "the device's temporal history", error);
    const VkCommandBuffer cb = d != nullptr ? d->recording(frame, error) : VK_NULL_HANDLE;
    if (cb == VK_NULL_HANDLE) return false;
    *decision = host_->decide(frame, traced, executor);
    d->frame.set_temporal(traced, *decision);
    return d->eye->record_temporal(cb, d->frame, executor, error);
  }
  std::size_t kept_rays() const override { return host_->kept_rays(); }

 private:
  std::unique_ptr<foveation::TemporalHistory> host_;
};

// Stage 6: the display transform, the encode into the shown image and its copy into the swapchain image.
class DeviceEncode final : public foveation::EncodeStage {
 public:
  bool encode(const foveation::FrameContext& frame, foveation::FrameResources& resources, foveation::Executor&,
              std::string* error) override {
    DeviceFrame* d = device_frame(resources, "the device's encode", error);
    const VkCommandBuffer cb = d != nullptr ? d->recording(frame, error) : VK_NULL_HANDLE;
    if (cb == VK_NULL_HANDLE) return false;
    d->eye->record_encode(cb, d->frame, d->image);
    d->eye->end_frame();
    return true;
  }
};

foveation::FrameStages make_device_stages(std::shared_ptr<const foveation::ViewTables> tables,
                                          const foveation::ViewSettings& settings, DeviceTraceEngine engine,
                                          std::unique_ptr<foveation::TemporalHistory> host_history) {
  if (tables == nullptr) throw std::invalid_argument("device stages: no tables");
  foveation::FrameStages stages;
  if (host_history == nullptr) host_history = foveation::make_temporal_history(*tables, settings);
  const bool keep_rays = host_history->keeps_rays();
  stages.history = std::make_unique<DeviceHistory>(std::move(host_history));
  if (engine) {
    stages.trace = std::make_unique<DeviceTraceStage>(tables, settings, std::move(engine));
  } else {
    stages.trace = std::make_unique<UploadedTrace>(foveation::make_callback_trace(tables, settings, keep_rays));
  }
  stages.reconstruct = std::make_unique<DeviceGather>(settings.rbf_clamp);
  stages.encode = std::make_unique<DeviceEncode>();
  return stages;
}

}  // namespace foveart::gpu
