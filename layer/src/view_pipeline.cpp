#include "view_pipeline.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>

#include "eye_math.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::layer {
namespace {

constexpr std::size_t kRaysPerBatch = 8192;
constexpr uint32_t kMaxHistoryFrames = 16;
constexpr uint64_t kSampleSeed = 0x5eed0f0e;

using Clock = std::chrono::steady_clock;
float ms_since(Clock::time_point t0) {
  return std::chrono::duration<float, std::milli>(Clock::now() - t0).count();
}

bool same_view(const ViewRequest& a, const ViewRequest& b) {
  return a.width_px == b.width_px && a.height_px == b.height_px && a.gaze_px == b.gaze_px &&
         std::memcmp(&a.pose, &b.pose, sizeof(XrPosef)) == 0 && std::memcmp(&a.fov, &b.fov, sizeof(XrFovf)) == 0;
}

const std::array<uint8_t, 4096>& srgb_table() {
  static const std::array<uint8_t, 4096> table = [] {
    std::array<uint8_t, 4096> t{};
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double c = static_cast<double>(i) / static_cast<double>(t.size() - 1);
      // IEC 61966-2-1 sRGB transfer function.
      const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
      t[i] = static_cast<uint8_t>(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
    }
    return t;
  }();
  return table;
}

}  // namespace

uint8_t encode_srgb8(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return srgb_table()[static_cast<std::size_t>(c * 4095.0f + 0.5f)];
}

ViewPipeline::ViewPipeline(std::shared_ptr<const ViewTables> tables) : tables_(std::move(tables)) {
  visible_of_point_.assign(tables_->points.size(), -1);
}

bool ViewPipeline::trace(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                         ViewOutcome* outcome) {
  const auto& points = tables_->points;
  auto t0 = Clock::now();
  const auto mapping = foveation::map_gaze(static_cast<int>(request.width_px), static_cast<int>(request.height_px),
                                           request.gaze_px);
  canvas_offset_x_ = mapping.canvas_from_screen_x_px;
  canvas_offset_y_ = mapping.canvas_from_screen_y_px;
  const auto visible = foveation::select_visible_points(points, mapping);
  const bool static_view = has_last_ && same_view(request, last_);
  const uint64_t seed = settings.taa && static_view ? kSampleSeed + history_frames_ : kSampleSeed;
  const auto samples =
      foveation::generate_ray_samples(points, visible, static_cast<int>(settings.rays_per_point), seed);

  for (uint32_t p : touched_points_) visible_of_point_[p] = -1;
  touched_points_.assign(visible.point_index.begin(), visible.point_index.end());
  for (std::size_t v = 0; v < visible.size(); ++v) visible_of_point_[visible.point_index[v]] = static_cast<int32_t>(v);

  const std::size_t n = samples.size();
  origins_.resize(n * 3);
  directions_.resize(n * 3);
  sample_px_.resize(n * 2);
  ray_rgb_.assign(n * 3, 0.0f);
  point_index_.assign(samples.point_index.begin(), samples.point_index.end());
  const EyeFrustum frustum = EyeFrustum::from(request.fov, static_cast<float>(request.width_px),
                                              static_cast<float>(request.height_px));
  const glm::quat orientation = to_glm(request.pose.orientation);
  const glm::vec3 position = to_glm(request.pose.position);
  const std::size_t batches = (n + kRaysPerBatch - 1) / kRaysPerBatch;
  pool.parallel_for(batches, [&](std::size_t b) {
    for (std::size_t i = b * kRaysPerBatch; i < std::min(n, (b + 1) * kRaysPerBatch); ++i) {
      const glm::vec2 s = samples.sample_px[i];  // screen pixels
      const glm::vec3 d = orientation * frustum.direction_view(s);
      std::memcpy(&origins_[i * 3], &position, sizeof(float) * 3);
      directions_[i * 3 + 0] = d.x;
      directions_[i * 3 + 1] = d.y;
      directions_[i * 3 + 2] = d.z;
      sample_px_[i * 2 + 0] = s.x;
      sample_px_[i * 2 + 1] = s.y;
    }
  });
  outcome->points = static_cast<uint32_t>(visible.size());
  outcome->rays = static_cast<uint32_t>(n);
  outcome->select_ms = ms_since(t0);

  // The engine answers in batches, several at once.
  t0 = Clock::now();
  FoveartEyeView view{};
  view.type = FOVEART_TYPE_EYE_VIEW;
  view.size = sizeof(view);
  view.eye_index = request.eye_index;
  view.width_px = request.width_px;
  view.height_px = request.height_px;
  std::memcpy(view.position_m, &request.pose.position, sizeof(view.position_m));
  std::memcpy(view.orientation_xyzw, &request.pose.orientation, sizeof(view.orientation_xyzw));
  view.angle_left_rad = request.fov.angleLeft;
  view.angle_right_rad = request.fov.angleRight;
  view.angle_up_rad = request.fov.angleUp;
  view.angle_down_rad = request.fov.angleDown;
  std::atomic<uint64_t> failed_batches{0};
  std::atomic<uint64_t> invalid{0};
  pool.parallel_for(batches, [&](std::size_t b) {
    const std::size_t first = b * kRaysPerBatch;
    const std::size_t count = std::min(n, first + kRaysPerBatch) - first;
    FoveartRayBatch batch{};
    batch.type = FOVEART_TYPE_RAY_BATCH;
    batch.size = sizeof(batch);
    batch.frame_index = request.frame_index;
    batch.view = &view;
    batch.ray_count = static_cast<uint32_t>(count);
    batch.origins_m = &origins_[first * 3];
    batch.directions = &directions_[first * 3];
    batch.sample_px = &sample_px_[first * 2];
    batch.point_index = &point_index_[first];
    batch.out_rgb = &ray_rgb_[first * 3];
    int32_t result = FOVEART_RESULT_ERROR_ENGINE_FAILURE;
    try {
      result = settings.trace_rays(settings.user_data, &batch);
    } catch (...) {  // a C++ engine without its own barrier
      result = FOVEART_RESULT_ERROR_ENGINE_FAILURE;
    }
    if (result != FOVEART_RESULT_SUCCESS) {
      failed_batches.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    uint64_t bad = 0;
    for (std::size_t i = first * 3; i < (first + count) * 3; ++i) {
      bad += !(std::isfinite(ray_rgb_[i]) && ray_rgb_[i] >= 0.0f);
    }
    if (bad != 0) invalid.fetch_add(bad, std::memory_order_relaxed);
  });
  outcome->trace_ms = ms_since(t0);
  outcome->callback_failures = failed_batches.load();
  outcome->invalid_colours = invalid.load();
  if (outcome->callback_failures != 0) {
    outcome->failure |= XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART;
    outcome->message = "the ray-trace callback failed " + std::to_string(outcome->callback_failures) + " batch(es)";
    return false;
  }
  if (outcome->invalid_colours != 0) {
    outcome->failure |= XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART;
    outcome->message = "the ray-trace callback returned " + std::to_string(outcome->invalid_colours) +
                       " NaN/Inf/negative colour components";
    return false;
  }

  // One colour per point: the mean of its samples (thesis 4.2).
  const uint32_t spp = settings.rays_per_point;
  point_rgb_.resize(visible.size());
  const float inv_spp = 1.0f / static_cast<float>(spp);
  for (std::size_t v = 0; v < visible.size(); ++v) {
    glm::vec3 sum(0.0f);
    for (uint32_t s = 0; s < spp; ++s) {
      const float* c = &ray_rgb_[(v * spp + s) * 3];
      sum += glm::vec3(c[0], c[1], c[2]);
    }
    point_rgb_[v] = sum * inv_spp;
  }
  return true;
}

void ViewPipeline::interpolate(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool) {
  const auto& points = tables_->points;
  const auto& table = tables_->neighbors;
  const uint32_t w = request.width_px;
  const uint32_t h = request.height_px;
  const int k = std::min(static_cast<int>(settings.k), table.k());
  const bool nearest = settings.interpolation == XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART || k == 1;
  image_.resize(std::size_t{w} * h);
  pool.parallel_for(h, [&](std::size_t y) {
    const int cy = static_cast<int>(y) + canvas_offset_y_;
    for (uint32_t x = 0; x < w; ++x) {
      const int cx = static_cast<int>(x) + canvas_offset_x_;
      const std::size_t pixel = std::size_t(cy) * std::size_t(table.width_px()) + std::size_t(cx);
      const glm::vec2 centre(static_cast<float>(cx) + 0.5f, static_cast<float>(cy) + 0.5f);
      std::array<float, foveation::kMaxNeighbors> dist{};
      std::array<int32_t, foveation::kMaxNeighbors> vis{};
      int used = 0;
      for (int j = 0; j < k; ++j) {
        const uint32_t p = table.neighbor(pixel, j);
        const int32_t v = visible_of_point_[p];
        if (v < 0) continue;
        vis[used] = v;
        dist[used] = glm::length(points.position_px[p] - centre);
        ++used;
        if (nearest) break;
      }
      glm::vec3 colour(0.0f);
      if (used == 1 || (used > 0 && dist[0] < 1e-4f)) {
        colour = point_rgb_[vis[0]];
      } else if (used > 1) {
        // Modified Shepard (Franke & Little; thesis 4.3): w_i = ((R - d_i)+ / (R d_i))^2,
        // R = distance of the farthest of the k neighbours.
        const float radius = dist[used - 1] * 1.0001f;
        float sum_w = 0.0f;
        for (int j = 0; j < used; ++j) {
          const float t = std::max(radius - dist[j], 0.0f) / (radius * dist[j]);
          const float wj = t * t;
          colour += wj * point_rgb_[vis[j]];
          sum_w += wj;
        }
        colour = sum_w > 0.0f ? colour / sum_w : point_rgb_[vis[0]];
      }
      image_[y * w + x] = colour;
    }
  });
}

void ViewPipeline::accumulate(bool static_view, WorkerPool& pool, uint32_t pixel_count) {
  // Temporal accumulation of jittered samples while view and gaze stay put; a
  // change restarts it (no reprojection: the history is dropped).
  history_frames_ = static_view ? std::min(history_frames_ + 1, kMaxHistoryFrames) : 1;
  if (history_frames_ == 1 || history_.size() != pixel_count) {
    history_ = image_;
    history_frames_ = 1;
    return;
  }
  const float alpha = 1.0f / static_cast<float>(history_frames_);
  const std::size_t rows = 64;
  const std::size_t chunk = (pixel_count + rows - 1) / rows;
  pool.parallel_for(rows, [&](std::size_t r) {
    for (std::size_t i = r * chunk; i < std::min<std::size_t>(pixel_count, (r + 1) * chunk); ++i) {
      history_[i] += (image_[i] - history_[i]) * alpha;
      image_[i] = history_[i];
    }
  });
}

ViewOutcome ViewPipeline::render(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                                 uint8_t* out_rgba, bool srgb) {
  ViewOutcome outcome;
  const bool static_view = has_last_ && same_view(request, last_);
  if (!trace(request, settings, pool, &outcome)) {
    has_last_ = false;
    history_frames_ = 0;
    return outcome;
  }
  auto t0 = Clock::now();
  interpolate(request, settings, pool);
  outcome.interpolate_ms = ms_since(t0);
  const uint32_t pixels = request.width_px * request.height_px;
  t0 = Clock::now();
  if (settings.taa) accumulate(static_view, pool, pixels);
  outcome.taa_ms = ms_since(t0);
  last_ = request;
  has_last_ = true;

  const std::size_t rows = request.height_px;
  pool.parallel_for(rows, [&](std::size_t y) {
    for (std::size_t x = 0; x < request.width_px; ++x) {
      const std::size_t i = y * request.width_px + x;
      const glm::vec3 c = image_[i];
      uint8_t* o = out_rgba + i * 4;
      if (srgb) {
        o[0] = encode_srgb8(c.r);
        o[1] = encode_srgb8(c.g);
        o[2] = encode_srgb8(c.b);
      } else {
        o[0] = static_cast<uint8_t>(std::lround(std::clamp(c.r, 0.0f, 1.0f) * 255.0f));
        o[1] = static_cast<uint8_t>(std::lround(std::clamp(c.g, 0.0f, 1.0f) * 255.0f));
        o[2] = static_cast<uint8_t>(std::lround(std::clamp(c.b, 0.0f, 1.0f) * 255.0f));
      }
      o[3] = 255;
    }
  });
  outcome.ok = true;
  return outcome;
}

}  // namespace foveart::layer
