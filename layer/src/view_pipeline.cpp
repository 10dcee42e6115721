#include "view_pipeline.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "eye_math.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/ray_samples.hpp"
#include "foveation/visible_points.hpp"

namespace foveart::layer {
namespace {

constexpr std::size_t kRaysPerBatch = 8192;
// The point set's seed too, so a static gaze without TAA gives what
// `fovea render --mode foveated` gives for the same view.
constexpr uint64_t kSampleSeed = 1;

using Clock = std::chrono::steady_clock;
float ms_since(Clock::time_point t0) {
  return std::chrono::duration<float, std::milli>(Clock::now() - t0).count();
}

bool same_view(const ViewRequest& a, const ViewRequest& b, bool with_gaze) {
  return a.width_px == b.width_px && a.height_px == b.height_px && (!with_gaze || a.gaze_px == b.gaze_px) &&
         std::memcmp(&a.pose, &b.pose, sizeof(XrPosef)) == 0 && std::memcmp(&a.fov, &b.fov, sizeof(XrFovf)) == 0;
}

}  // namespace

foveation::InterpOptions interp_options(const RendererSettings& settings) {
  foveation::InterpOptions o;
  switch (settings.interpolation) {
    case XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART: o.method = foveation::InterpMethod::nn; break;
    case XR_FOVEATED_INTERPOLATION_RBF_FOVEART: o.method = foveation::InterpMethod::rbf_mq; break;
    default: o.method = foveation::InterpMethod::msm; break;
  }
  o.k = o.method == foveation::InterpMethod::nn ? 1 : static_cast<int>(settings.k);
  return o;
}

int neighbor_count(const RendererSettings& settings) {
  const auto o = interp_options(settings);
  return o.method == foveation::InterpMethod::nn ? 4 : o.k;
}

std::shared_ptr<const ViewTables> load_view_tables(const foveation::PointSetKey& key, const RendererSettings& settings,
                                                   const std::optional<std::filesystem::path>& cache_dir) {
  auto out = std::make_shared<ViewTables>();
  auto tables = foveation::load_or_build_tables(cache_dir, key);
  out->points = std::move(tables.points);
  out->neighbors = std::move(tables.neighbors);
  auto interp = foveation::load_or_build_interpolation_table(cache_dir, key, out->points, out->neighbors,
                                                             interp_options(settings));
  out->interpolation = std::move(interp.table);
  return out;
}

ViewPipeline::ViewPipeline(std::shared_ptr<const ViewTables> tables, std::size_t points_per_chunk)
    : tables_(std::move(tables)), points_per_chunk_(std::max<std::size_t>(1, points_per_chunk)) {}

bool ViewPipeline::trace(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                         ViewOutcome* outcome) {
  const auto& points = tables_->points;
  auto t0 = Clock::now();
  mapping_ = foveation::map_gaze(static_cast<int>(request.width_px), static_cast<int>(request.height_px),
                                 request.gaze_px);
  if (settings.rays_per_point < 1) throw std::invalid_argument("rays per point must be >= 1");
  const std::size_t spp = settings.rays_per_point;
  // With TAA, new jitter every frame so the history converges; without, fixed samples.
  const uint64_t seed = settings.taa ? kSampleSeed + request.frame_index : kSampleSeed;
  const EyeFrustum frustum = EyeFrustum::from(request.fov, static_cast<float>(request.width_px),
                                              static_cast<float>(request.height_px));
  const glm::quat orientation = to_glm(request.pose.orientation);
  const glm::vec3 position = to_glm(request.pose.position);

  // Selection on the pool (thesis 4.2), in two passes over chunks of the point
  // set: scan each chunk for visible points, then, at each chunk's offset in
  // the concatenation, its ray samples and rays. Same order and values as
  // select_visible_points + generate_ray_samples on one thread.
  const std::size_t chunk_count = std::max<std::size_t>(1, (points.size() + points_per_chunk_ - 1) / points_per_chunk_);
  chunks_.resize(chunk_count);
  chunk_samples_.resize(chunk_count);
  pool.parallel_for(chunk_count, [&](std::size_t c) {
    auto& chunk = chunks_[c];
    chunk.point_index.clear();
    chunk.screen_px.clear();
    foveation::select_visible_points_in(points, mapping_, foveation::kVisibleMarginPx, c * points_per_chunk_,
                                        (c + 1) * points_per_chunk_, &chunk);
  });
  chunk_offset_.resize(chunk_count + 1);
  chunk_offset_[0] = 0;
  for (std::size_t c = 0; c < chunk_count; ++c) chunk_offset_[c + 1] = chunk_offset_[c] + chunks_[c].size();
  const std::size_t visible_count = chunk_offset_[chunk_count];
  const std::size_t n = visible_count * spp;
  visible_index_.resize(visible_count);
  origins_.resize(n * 3);
  directions_.resize(n * 3);
  sample_px_.resize(n * 2);
  ray_rgb_.assign(n * 3, 0.0f);
  point_index_.resize(n);
  pool.parallel_for(chunk_count, [&](std::size_t c) {
    const auto& chunk = chunks_[c];
    const std::size_t first_visible = chunk_offset_[c];
    std::copy(chunk.point_index.begin(), chunk.point_index.end(), visible_index_.begin() + static_cast<std::ptrdiff_t>(first_visible));
    auto& samples = chunk_samples_[c];
    samples.resize(chunk.size() * spp);
    const std::size_t first = first_visible * spp;
    foveation::write_ray_samples(points, chunk, static_cast<int>(spp), seed, samples.data(),
                                 point_index_.data() + first);
    for (std::size_t j = 0; j < samples.size(); ++j) {
      const std::size_t i = first + j;
      const glm::vec2 s = samples[j];  // screen pixels
      const glm::vec3 d = orientation * frustum.direction_view(s);
      std::memcpy(&origins_[i * 3], &position, sizeof(float) * 3);
      directions_[i * 3 + 0] = d.x;
      directions_[i * 3 + 1] = d.y;
      directions_[i * 3 + 2] = d.z;
      sample_px_[i * 2 + 0] = s.x;
      sample_px_[i * 2 + 1] = s.y;
    }
  });
  const std::size_t batches = (n + kRaysPerBatch - 1) / kRaysPerBatch;
  outcome->points = static_cast<uint32_t>(visible_count);
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
  point_rgb_.resize(visible_count * 3);
  const float inv_spp = 1.0f / static_cast<float>(spp);
  pool.parallel_for((visible_count + kRaysPerBatch - 1) / kRaysPerBatch, [&](std::size_t b) {
    for (std::size_t v = b * kRaysPerBatch; v < std::min(visible_count, (b + 1) * kRaysPerBatch); ++v) {
      glm::vec3 sum(0.0f);
      for (std::size_t s = 0; s < spp; ++s) {
        const float* c = &ray_rgb_[(v * spp + s) * 3];
        sum += glm::vec3(c[0], c[1], c[2]);
      }
      const glm::vec3 mean = sum * inv_spp;
      point_rgb_[v * 3 + 0] = mean.r;
      point_rgb_[v * 3 + 1] = mean.g;
      point_rgb_[v * 3 + 2] = mean.b;
    }
  });
  return true;
}

ViewOutcome ViewPipeline::render(const ViewRequest& request, const RendererSettings& settings, WorkerPool& pool,
                                 uint8_t* out_rgba, bool srgb) {
  ViewOutcome outcome;
  const bool same_pose = has_last_ && same_view(request, last_, false);
  if (!trace(request, settings, pool, &outcome)) {
    has_last_ = false;
    taa_.reset();
    return outcome;
  }
  // Thesis 4.3: every pixel a k-tap gather over the precomputed canvas weights.
  auto t0 = Clock::now();
  const auto colours = foveation::point_colors_from_list(tables_->points.size(), visible_index_, point_rgb_);
  foveation::GatherOptions gather_options;
  gather_options.threads = static_cast<int>(pool.size());
  foveation::gather(tables_->neighbors, tables_->interpolation, colours, mapping_, image_, gather_options);
  outcome.interpolate_ms = ms_since(t0);
  t0 = Clock::now();
  const foveation::ImageRgb* shown = &image_;
  if (settings.taa) {
    // No reprojection: a head move restarts the history (a gaze jump does inside).
    if (!same_pose) taa_.reset();
    shown = &taa_.accumulate(image_, mapping_.gaze_px);
  }
  outcome.taa_ms = ms_since(t0);
  last_ = request;
  has_last_ = true;

  const std::size_t rows = request.height_px;
  pool.parallel_for(rows, [&](std::size_t y) {
    for (std::size_t x = 0; x < request.width_px; ++x) {
      const std::size_t i = y * request.width_px + x;
      const float* p = shown->rgb.data() + i * 3;
      const glm::vec3 c(p[0], p[1], p[2]);
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
