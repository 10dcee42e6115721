// The sample-history control (sample_history.hpp).
#include "sample_history.hpp"

#include <foveation/eye_rays.hpp>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace foveart::tools {
namespace {

constexpr std::size_t kBatchRays = 4096;

// Pixels a ray reaches either side of its own: the filter's support is 1 px (box) or 3 px (bspline2).
int reach_px(foveation::PixelFilter filter) { return filter == foveation::PixelFilter::box ? 0 : 1; }

}  // namespace

// Box: the pixel, [-0.5, 0.5) as floor() assigns rays to pixels; bspline2:
// box * box * box on (-1.5, 1.5) around the centre (Unser 1999).
float pixel_filter_weight(foveation::PixelFilter filter, float offset_px) {
  if (filter == foveation::PixelFilter::box) return offset_px >= -0.5f && offset_px < 0.5f ? 1.0f : 0.0f;
  const float u = std::fabs(offset_px);
  if (u < 0.5f) return 0.75f - u * u;
  if (u < 1.5f) return 0.5f * (1.5f - u) * (1.5f - u);
  return 0.0f;
}

std::int32_t SampleHistory::render(FoveartTraceRaysFn fn, void* user_data, const FoveartEyeView& view,
                                   std::uint64_t frame_index, bool restart, foveation::Executor& executor,
                                   foveation::ImageRgb* out_linear) {
  const int width = int(view.width_px), height = int(view.height_px);
  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  const foveation::EyeFrustum frustum = foveation::eye_frustum(view);
  const foveation::EyePose pose = foveation::eye_pose(view);
  const int reach = reach_px(filter_);
  if (restart) anchors_.clear();
  const std::size_t kept = anchors_.size(), rays = kept + pixels;
  anchors_.resize(rays);
  sample_px_.resize(rays);
  on_screen_.resize(rays);
  rgb_.resize(rays);
  batches_.resize(executor.thread_count());

  // Every ray: a kept one where its anchor projects from the current eye, a
  // new one jittered in its pixel; traced from the current eye in batches
  // (a kept one only with RayReuse::retrace).
  const bool retrace = reuse_ == RayReuse::retrace;
  if (!retrace) new_depth_m_.assign(pixels, INFINITY);
  std::atomic<std::int32_t> status{FOVEART_RESULT_SUCCESS};
  executor.parallel_for((rays + kBatchRays - 1) / kBatchRays, [&](std::size_t chunk, unsigned worker) {
    const std::size_t begin = chunk * kBatchRays, end = std::min(rays, begin + kBatchRays);
    foveation::RayBatch& b = batches_[worker];
    b.resize(end - begin);
    std::uint32_t traced = 0;
    for (std::size_t i = begin; i < end; ++i) {
      glm::vec2 q;
      if (i < kept) {
        const Anchor& a = anchors_[i];
        const glm::vec3 direction =
            a.at_infinity ? a.point_m_or_direction : glm::normalize(a.point_m_or_direction - pose.position_m);
        const float r = float(reach);
        on_screen_[i] = foveation::project_direction(frustum, pose, direction, &q) && q.x > -r &&
                        q.x < float(width) + r && q.y > -r && q.y < float(height) + r;
      } else {
        const std::uint64_t p = i - kept;
        q = glm::vec2(float(p % std::uint64_t(width)), float(p / std::uint64_t(width))) +
            foveation::pixel_jitter(p, 0, seed_ + frame_index, filter_);
        on_screen_[i] = 1;
      }
      sample_px_[i] = q;
      if (i < kept && !retrace) {
        rgb_[i] = anchors_[i].rgb;
      } else if (on_screen_[i]) {
        b.set_ray(traced++, frustum, pose, q, std::uint32_t(i));
      }
    }
    const std::int32_t st = b.trace(fn, user_data, view, frame_index, traced);
    if (st != FOVEART_RESULT_SUCCESS) {
      std::int32_t expected = FOVEART_RESULT_SUCCESS;
      status.compare_exchange_strong(expected, st);
      return;
    }
    std::uint32_t k = 0;
    for (std::size_t i = retrace ? begin : std::max(begin, kept); i < end; ++i) {  // the traced ones
      if (!on_screen_[i]) continue;
      rgb_[i] = b.rgb(k);
      if (i >= kept) {  // a new ray's anchor: where it hit, or its direction for a miss (or no depth)
        const glm::vec3 direction = foveation::eye_ray_direction(frustum, pose, sample_px_[i]);
        const float d = b.depth_m(k);
        anchors_[i] = std::isfinite(d) ? Anchor{pose.position_m + direction * d, false, rgb_[i]}
                                       : Anchor{direction, true, rgb_[i]};
        if (!retrace && std::isfinite(d)) new_depth_m_[i - kept] = d;
      }
      ++k;
    }
  });
  if (status.load() != FOVEART_RESULT_SUCCESS) {
    anchors_.resize(kept);
    return status.load();
  }
  if (!retrace) drop_covered_rays(kept, pose, width, height, executor);

  // The on-screen rays by pixel row (a stable counting sort: the sums below
  // run in one order whatever the thread count), rows -reach .. height - 1 + reach.
  const int rows = height + 2 * reach;
  auto row_of = [&](std::size_t i) {
    return std::clamp(int(std::floor(sample_px_[i].y)), -reach, height - 1 + reach) + reach;
  };
  row_begin_.assign(std::size_t(rows) + 1, 0);
  for (std::size_t i = 0; i < rays; ++i)
    if (on_screen_[i]) ++row_begin_[std::size_t(row_of(i)) + 1];
  for (int r = 0; r < rows; ++r) row_begin_[std::size_t(r) + 1] += row_begin_[std::size_t(r)];
  by_row_.resize(row_begin_.back());
  {
    std::vector<std::uint32_t> next(row_begin_.begin(), row_begin_.end() - 1);
    for (std::size_t i = 0; i < rays; ++i)
      if (on_screen_[i]) by_row_[next[std::size_t(row_of(i))]++] = std::uint32_t(i);
  }

  // Each pixel: sum(w L) / sum(w) over the rays within the filter's reach (pbrt-v4 8.8).
  if (out_linear->width_px != width || out_linear->height_px != height) *out_linear = foveation::ImageRgb(width, height);
  executor.parallel_for(std::size_t(height), [&](std::size_t row) {
    const int y = int(row);
    std::vector<glm::vec4> sum(std::size_t(width), glm::vec4(0.0f));  // rgb, weight
    for (int r = y; r <= y + 2 * reach; ++r)  // sample rows y - reach .. y + reach, offset by reach
      for (std::uint32_t k = row_begin_[std::size_t(r)]; k < row_begin_[std::size_t(r) + 1]; ++k) {
        const std::uint32_t i = by_row_[k];
        const glm::vec2 q = sample_px_[i];
        const float wy = pixel_filter_weight(filter_, q.y - (float(y) + 0.5f));
        if (wy == 0.0f) continue;
        const int cx = int(std::floor(q.x));
        for (int x = std::max(0, cx - reach); x <= std::min(width - 1, cx + reach); ++x) {
          const float w = wy * pixel_filter_weight(filter_, q.x - (float(x) + 0.5f));
          sum[std::size_t(x)] += glm::vec4(w * rgb_[i], w);
        }
      }
    for (int x = 0; x < width; ++x) {
      const glm::vec4 s = sum[std::size_t(x)];
      float* px = out_linear->at(x, y);
      for (int c = 0; c < 3; ++c) px[c] = s.w > 0.0f ? s[c] / s.w : 0.0f;
    }
  });

  // Keep the rays still within reach: the old ones that stayed, every new one.
  std::size_t n = 0;
  for (std::size_t i = 0; i < rays; ++i)
    if (on_screen_[i]) anchors_[n++] = anchors_[i];
  anchors_.resize(n);
  return FOVEART_RESULT_SUCCESS;
}

// The render cache's depth test (Walter et al. 1999): a kept hit farther
// than every new ray this frame drew for the 3x3 pixels around its own, or a
// kept miss where all of them hit, is hidden now and forgotten. One pixel's
// new ray alone would not do: at an edge inside the pixel it lands on the
// nearer surface in some frames, and the farther surface's kept rays there
// are still seen (RayCache.StillViewTracesOnlyTheNewRaysAndMatchesTheRetracedHistory
// fails that way). The price: a kept ray within a pixel of an occluder's edge
// stays until the occluder covers its neighbours too. Off the image (within
// the filter's reach) there is no new ray to compare with: the kept ray stays.
void SampleHistory::drop_covered_rays(std::size_t kept, const foveation::EyePose& pose, int width, int height,
                                      foveation::Executor& executor) {
  executor.parallel_for((kept + kBatchRays - 1) / kBatchRays, [&](std::size_t chunk, unsigned) {
    for (std::size_t i = chunk * kBatchRays, end = std::min(kept, i + kBatchRays); i < end; ++i) {
      if (!on_screen_[i]) continue;
      const int x = int(std::floor(sample_px_[i].x)), y = int(std::floor(sample_px_[i].y));
      if (x < 0 || y < 0 || x >= width || y >= height) continue;
      float farthest_new_m = 0.0f;  // +inf once one of them missed
      for (int ny = std::max(0, y - 1); ny <= std::min(height - 1, y + 1); ++ny)
        for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx)
          farthest_new_m =
              std::max(farthest_new_m, new_depth_m_[std::size_t(ny) * std::size_t(width) + std::size_t(nx)]);
      if (!std::isfinite(farthest_new_m)) continue;
      const Anchor& a = anchors_[i];
      const bool covered =
          a.at_infinity ||
          glm::length(a.point_m_or_direction - pose.position_m) > farthest_new_m * (1.0f + kKeptRayOcclusionTolerance);
      if (covered) on_screen_[i] = 0;
    }
  });
}

}  // namespace foveart::tools
