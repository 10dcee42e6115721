// The sample-history control (sample_history.hpp).
#include <eval/sample_history.hpp>

#include <algorithm>
#include <atomic>

namespace foveart::eval {
namespace {

constexpr std::size_t kBatchRays = 4096;

}  // namespace

std::int32_t SampleHistory::render(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                                   std::uint64_t frame_index, bool restart, foveation::Executor& executor,
                                   foveation::ImageRgb* out_linear) {
  const int width = int(view.width_px), height = int(view.height_px);
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  if (restart) cache_.clear();
  cache_.begin_frame(view, executor);
  const std::size_t kept = cache_.kept();
  const std::size_t first_new = cache_.add_rays(pixels);
  batches_.resize(executor.thread_count());

  // Every ray traced from the current eye in batches: a new one jittered in
  // its pixel, a kept one (RayReuse::retrace only) where its anchor projects.
  const bool retrace = reuse_ == RayReuse::retrace;
  const std::size_t first_traced = retrace ? 0 : first_new, rays = first_new + pixels;
  std::atomic<std::int32_t> status{FOVEART_RESULT_SUCCESS};
  executor.parallel_for((rays - first_traced + kBatchRays - 1) / kBatchRays, [&](std::size_t chunk, unsigned worker) {
    const std::size_t begin = first_traced + chunk * kBatchRays, end = std::min(rays, begin + kBatchRays);
    foveation::RayBatch& b = batches_[worker];
    b.resize(end - begin);
    std::uint32_t traced = 0;
    for (std::size_t i = begin; i < end; ++i) {
      if (i < kept) {
        if (cache_.kept_on_screen(i)) b.set_sample(traced++, cache_.kept_sample_px(i), std::uint32_t(i));
      } else {
        const std::uint64_t p = i - first_new;
        const glm::vec2 q = glm::vec2(float(p % std::uint64_t(width)), float(p / std::uint64_t(width))) +
                            foveation::pixel_jitter(p, 0, seed_ + frame_index, cache_.options().filter);
        b.set_sample(traced++, q, std::uint32_t(i));
      }
    }
    const std::int32_t st = b.trace(fn, user_data, view, frame_index, traced);
    if (st != FOVEART_RESULT_SUCCESS) {
      std::int32_t expected = FOVEART_RESULT_SUCCESS;
      status.compare_exchange_strong(expected, st);
      return;
    }
    for (std::uint32_t k = 0; k < traced; ++k) {
      const std::size_t i = b.point(k);
      if (i < kept) {
        cache_.set_kept_rgb(i, b.rgb(k));
      } else {
        const std::size_t p = i - first_new;  // the pixel it was drawn for
        cache_.set_ray(i, b.sample_px(k), b.rgb(k), b.depth_m(k),
                       glm::ivec2(int(p % std::size_t(width)), int(p / std::size_t(width))));
      }
    }
  });
  if (status.load() != FOVEART_RESULT_SUCCESS) {
    cache_.abandon_frame();
    return status.load();
  }
  cache_.resolve(executor, out_linear);
  return FOVEART_RESULT_SUCCESS;
}

}  // namespace foveart::eval
