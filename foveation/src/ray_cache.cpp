// The render cache (ray_cache.hpp).
#include "foveation/ray_cache.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace foveart::foveation {
namespace {

constexpr std::size_t kChunkRays = 4096;
// filter_at's grid: cells of this many pixels, and at most this many chunks of
// rays counted apart (its counts are chunks x cells).
constexpr int kCellPx = FOVEART_RAY_CACHE_CELL_PX;
constexpr std::size_t kMaxCellChunks = 16;

// Pixels a ray reaches either side of its own: the filter's support is 1 px (box) or 3 px (bspline2).
int reach_px(PixelFilter filter) { return filter == PixelFilter::box ? 0 : 1; }

// The middle of a counting sort per chunk, stable (chunk by chunk, each in
// order, so sums over a bucket run in one order whatever the thread count):
// chunk_counts[c * buckets + b], how many of chunk c fall in bucket b, become
// where chunk c's first one in bucket b goes; bucket b starts at begin[b],
// and begin[buckets] is the total.
void counting_sort_offsets(std::vector<std::uint32_t>& chunk_counts, std::size_t chunks, std::size_t buckets,
                           std::vector<std::uint32_t>& begin) {
  begin.assign(buckets + 1, 0);
  std::uint32_t at = 0;
  for (std::size_t b = 0; b < buckets; ++b) {
    begin[b] = at;
    for (std::size_t c = 0; c < chunks; ++c) {
      const std::uint32_t n = chunk_counts[c * buckets + b];
      chunk_counts[c * buckets + b] = at;
      at += n;
    }
  }
  begin[buckets] = at;
}

}  // namespace

void RayCache::begin_frame(const FoveartEyeView& view, Executor& executor) {
  width_px_ = int(view.width_px);
  height_px_ = int(view.height_px);
  frustum_ = eye_frustum(view);
  pose_ = eye_pose(view);
  kept_ = anchors_.size();
  covered_forgotten_ = false;
  sample_px_.resize(kept_);
  row_.resize(kept_);
  drawn_pixel_.clear();
  executor.parallel_chunks(kept_, kChunkRays, [&](std::size_t first, std::size_t last, unsigned) {
    for (std::size_t i = first; i < last; ++i) {
      const Anchor& a = anchors_[i];
      const glm::vec3 direction =
          a.at_infinity ? a.point_m_or_direction : glm::normalize(a.point_m_or_direction - pose_.position_m);
      glm::vec2 q(0.0f);
      const bool projects = project_direction(frustum_, pose_, direction, &q);
      sample_px_[i] = q;
      row_[i] = projects ? row_within_reach(q) : -1;
    }
  });
}

std::size_t RayCache::add_rays(std::size_t n) {
  const std::size_t first = anchors_.size();
  anchors_.resize(first + n);
  sample_px_.resize(first + n);
  row_.resize(first + n);
  drawn_pixel_.resize(first + n - kept_);
  return first;
}

void RayCache::set_ray(std::size_t i, glm::vec2 sample_px, glm::vec3 rgb, float depth_m, glm::ivec2 drawn_pixel) {
  const glm::vec3 direction = eye_ray_direction(frustum_, pose_, sample_px);
  anchors_[i] = std::isfinite(depth_m) && depth_m >= 0.0f
                    ? Anchor{pose_.position_m + direction * depth_m, rgb, 0, false}
                    : Anchor{direction, rgb, 0, true};
  sample_px_[i] = sample_px;
  row_[i] = row_within_reach(sample_px);
  const bool on_image =
      drawn_pixel.x >= 0 && drawn_pixel.y >= 0 && drawn_pixel.x < width_px_ && drawn_pixel.y < height_px_;
  drawn_pixel_[i - kept_] = on_image ? drawn_pixel.y * width_px_ + drawn_pixel.x : -1;
}

int RayCache::row_within_reach(glm::vec2 q) const {
  const int reach = reach_px(options_.filter);
  const float r = float(reach);
  const bool within = q.x >= -r && q.x < float(width_px_) + r && q.y >= -r && q.y < float(height_px_) + r;
  return within ? int(std::floor(q.y)) + reach : -1;
}

float RayCache::distance_m(std::size_t i) const {
  const Anchor& a = anchors_[i];
  return a.at_infinity ? INFINITY : glm::length(a.point_m_or_direction - pose_.position_m);
}

void RayCache::filter_at(const std::vector<glm::vec2>& centres_px, const std::vector<float>& footprint_px,
                         Executor& executor, std::vector<glm::vec3>* out_rgb, std::vector<float>* out_weight) {
  forget_covered_once(executor);
  const std::size_t centres = centres_px.size();
  out_rgb->resize(centres);
  out_weight->assign(centres, 0.0f);
  if (centres == 0) return;
  // The filter's half-width in footprints, and the cell grid: it starts one
  // cell before the image, so it holds every ray within reach (at most 1 px beyond).
  const float half_width = options_.filter == PixelFilter::box ? 0.5f : 1.5f;
  const int cells_x = (width_px_ + 2 * kCellPx - 1) / kCellPx + 1, cells_y = (height_px_ + 2 * kCellPx - 1) / kCellPx + 1;
  auto cell_range = [&](glm::vec2 centre, float footprint, glm::ivec2* lo, glm::ivec2* hi) {
    const CellRange cells = filter_window_cells(centre, half_width * footprint);
    *lo = glm::max(cells.first, glm::ivec2(0));
    *hi = glm::min(cells.last, glm::ivec2(cells_x - 1, cells_y - 1));
  };
  // The cells some centre reaches (one pass: a centre's cells overlap its neighbours').
  cell_needed_.assign(std::size_t(cells_x) * std::size_t(cells_y), 0);
  for (std::size_t j = 0; j < centres; ++j) {
    glm::ivec2 lo, hi;
    cell_range(centres_px[j], footprint_px[j], &lo, &hi);
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) cell_needed_[std::size_t(cy) * std::size_t(cells_x) + std::size_t(cx)] = 1;
  }
  // The rays in those cells, by cell: a stable counting sort per chunk of rays, as in resolve.
  const std::size_t rays = anchors_.size(), cells = cell_needed_.size();
  const std::size_t chunks = std::clamp<std::size_t>((rays + kChunkRays - 1) / kChunkRays, 1, kMaxCellChunks);
  const std::size_t chunk_rays = (rays + chunks - 1) / chunks;
  cell_.resize(rays);
  chunk_cells_.assign(chunks * cells, 0);
  executor.parallel_for(chunks, [&](std::size_t c) {
    std::uint32_t* count = chunk_cells_.data() + c * cells;
    for (std::size_t i = c * chunk_rays, end = std::min(rays, i + chunk_rays); i < end; ++i) {
      cell_[i] = -1;
      if (row_[i] < 0) continue;
      const glm::ivec2 cell = ray_cache_cell(sample_px_[i]);
      if (cell.x < 0 || cell.y < 0 || cell.x >= cells_x || cell.y >= cells_y) continue;
      const std::size_t k = std::size_t(cell.y) * std::size_t(cells_x) + std::size_t(cell.x);
      if (cell_needed_[k] == 0) continue;
      cell_[i] = std::int32_t(k);
      ++count[k];
    }
  });
  counting_sort_offsets(chunk_cells_, chunks, cells, cell_begin_);
  by_cell_.resize(cell_begin_[cells]);
  executor.parallel_for(chunks, [&](std::size_t c) {
    std::uint32_t* next = chunk_cells_.data() + c * cells;
    for (std::size_t i = c * chunk_rays, end = std::min(rays, i + chunk_rays); i < end; ++i)
      if (cell_[i] >= 0) by_cell_[next[cell_[i]]++] = CellSample{sample_px_[i], anchors_[i].rgb};
  });
  // Each centre: sum(w L) / sum(w) over the rays within its scaled filter (pbrt-v4 8.8).
  executor.parallel_chunks(centres, 256, [&](std::size_t first, std::size_t last, unsigned) {
    for (std::size_t j = first; j < last; ++j) {
      const glm::vec2 centre = centres_px[j];
      const float inv_footprint = 1.0f / footprint_px[j];
      glm::ivec2 lo, hi;
      cell_range(centre, footprint_px[j], &lo, &hi);
      glm::vec4 sum(0.0f);
      for (int cy = lo.y; cy <= hi.y; ++cy)
        for (int cx = lo.x; cx <= hi.x; ++cx) {
          const std::size_t k = std::size_t(cy) * std::size_t(cells_x) + std::size_t(cx);
          for (std::uint32_t s = cell_begin_[k]; s < cell_begin_[k + 1]; ++s) {
            const glm::vec2 t = (by_cell_[s].sample_px - centre) * inv_footprint;
            if (t.x < -half_width || t.x >= half_width || t.y < -half_width || t.y >= half_width) continue;
            const float w = pixel_filter_weight(options_.filter, t.x) * pixel_filter_weight(options_.filter, t.y);
            sum += glm::vec4(w * by_cell_[s].rgb, w);
          }
        }
      (*out_weight)[j] = sum.w;
      if (sum.w > 0.0f) (*out_rgb)[j] = glm::vec3(sum) / sum.w;
    }
  });
}

void RayCache::resolve(Executor& executor, ImageRgb* out_linear, std::vector<float>* out_weight) {
  forget_covered_once(executor);
  sort_by_row(executor);
  filter_rows(executor, out_linear, out_weight);
  keep_young_rays();
}

// The within-reach rays by pixel row, rows -reach .. height - 1 + reach, into
// by_row_: a counting sort per chunk of rays, stable (chunk by chunk, each in
// order), so the sums of filter_rows run in one order whatever the thread count.
void RayCache::sort_by_row(Executor& executor) {
  const std::size_t rays = anchors_.size();
  const std::size_t rows = std::size_t(height_px_ + 2 * reach_px(options_.filter));
  const std::size_t chunks = (rays + kChunkRays - 1) / kChunkRays;
  chunk_rows_.assign(chunks * rows, 0);
  executor.parallel_for(chunks, [&](std::size_t c) {
    std::uint32_t* count = chunk_rows_.data() + c * rows;
    for (std::size_t i = c * kChunkRays, end = std::min(rays, i + kChunkRays); i < end; ++i)
      if (row_[i] >= 0) ++count[row_[i]];
  });
  counting_sort_offsets(chunk_rows_, chunks, rows, row_begin_);
  by_row_.resize(row_begin_[rows]);
  executor.parallel_for(chunks, [&](std::size_t c) {
    std::uint32_t* next = chunk_rows_.data() + c * rows;
    for (std::size_t i = c * kChunkRays, end = std::min(rays, i + kChunkRays); i < end; ++i)
      if (row_[i] >= 0) {
        const glm::vec2 q = sample_px_[i];
        Sample& sample = by_row_[next[row_[i]]++];
        sample.rgb = anchors_[i].rgb;
        const glm::vec2 pixel = glm::floor(q);
        sample.x_px = int(pixel.x);
        sample.t_px = q - pixel - 0.5f;
      }
  });
}

// Each pixel: sum(w L) / sum(w) over the rays within the filter's reach (pbrt-v4 8.8).
void RayCache::filter_rows(Executor& executor, ImageRgb* out_linear, std::vector<float>* out_weight) const {
  const int width = width_px_, height = height_px_;
  const int reach = reach_px(options_.filter);
  if (out_linear->width_px != width || out_linear->height_px != height) *out_linear = ImageRgb(width, height);
  if (out_weight != nullptr) out_weight->assign(std::size_t(width) * std::size_t(height), 0.0f);
  executor.parallel_for(std::size_t(height), [&](std::size_t row) {
    const int y = int(row);
    std::vector<glm::vec4> sum(std::size_t(width), glm::vec4(0.0f));  // rgb, weight
    // Sample rows y - reach .. y + reach (row_ is offset by reach): a ray
    // within reach of the image lies in [-reach, size + reach), so its row is floor(y).
    for (int r = y; r <= y + 2 * reach; ++r) {
      const std::uint32_t begin = row_begin_[std::size_t(r)], end = row_begin_[std::size_t(r) + 1];
      if (reach == 0) {  // box: the ray's own pixel
        for (std::uint32_t k = begin; k < end; ++k) {
          const int x = by_row_[k].x_px;
          if (x >= 0 && x < width) sum[std::size_t(x)] += glm::vec4(by_row_[k].rgb, 1.0f);
        }
        continue;
      }
      // This output row is the sample row's row before (0), own (1) or after (2).
      const int weight_index = y + reach - r + 1;
      for (std::uint32_t k = begin; k < end; ++k) {
        const Sample& sample = by_row_[k];
        float wx[3], wy[3];
        bspline2_weights(sample.t_px.x, wx);
        bspline2_weights(sample.t_px.y, wy);
        const float w_row = wy[weight_index];
        for (int j = 0; j < 3; ++j) {
          const int x = sample.x_px - 1 + j;
          if (x < 0 || x >= width) continue;
          const float w = w_row * wx[j];
          sum[std::size_t(x)] += glm::vec4(w * sample.rgb, w);
        }
      }
    }
    for (int x = 0; x < width; ++x) {
      const glm::vec4 s = sum[std::size_t(x)];
      float* px = out_linear->at(x, y);
      for (int c = 0; c < 3; ++c) px[c] = s.w > 0.0f ? s[c] / s.w : 0.0f;
      if (out_weight != nullptr) (*out_weight)[std::size_t(y) * std::size_t(width) + std::size_t(x)] = s.w;
    }
  });
}

// Keeps the rays still within reach and young enough to see the next frame, in order, in place.
void RayCache::keep_young_rays() {
  const std::uint32_t max_age = options_.max_age_frames;
  std::size_t n = 0;
  for (std::size_t i = 0; i < anchors_.size(); ++i) {
    if (row_[i] < 0 || (max_age != 0 && anchors_[i].age_frames + 1 >= max_age)) continue;
    anchors_[n] = anchors_[i];
    ++anchors_[n++].age_frames;
  }
  anchors_.resize(n);
  kept_ = 0;
}

void farthest_around_3x3(const std::vector<float>& farthest_drawn_m, int width_px, int height_px, Executor& executor,
                         std::vector<float>* out_m) {
  const std::size_t width = std::size_t(width_px), height = std::size_t(height_px);
  out_m->resize(width * height);
  executor.parallel_for(height, [&](std::size_t y) {
    for (std::size_t x = 0; x < width; ++x) {
      float farthest_m = 0.0f;
      for (std::size_t ny = y == 0 ? 0 : y - 1; ny <= std::min(height - 1, y + 1); ++ny)
        for (std::size_t nx = x == 0 ? 0 : x - 1; nx <= std::min(width - 1, x + 1); ++nx) {
          const float d = farthest_drawn_m[ny * width + nx];
          farthest_m = std::max(farthest_m, d < 0.0f ? INFINITY : d);
        }
      (*out_m)[y * width + x] = farthest_m;
    }
  });
}

// The render cache's depth test (Walter et al. 1999): a kept hit farther
// than every new ray this frame drew for the 3x3 pixels around its own, or a
// kept miss where all of them hit, is hidden now and forgotten. One pixel's
// new ray alone would not do: at an edge inside the pixel it lands on the
// nearer surface in some frames, and the farther surface's kept rays there
// are still seen (RayCache.StillViewTracesOnlyTheNewRaysAndMatchesTheRetracedHistory
// fails that way). The price: a kept ray within a pixel of an occluder's edge
// stays until the occluder covers its neighbours too. A pixel without a new
// ray (off the image, or between the sparse points of the periphery) or with
// one that returned no depth cannot tell: the kept ray stays.
void RayCache::forget_covered(Executor& executor) {
  const std::size_t width = std::size_t(width_px_), height = std::size_t(height_px_);
  new_depth_m_.assign(width * height, -1.0f);
  for (std::size_t i = kept_; i < anchors_.size(); ++i) {
    const std::int32_t pixel = drawn_pixel_[i - kept_];
    if (pixel < 0) continue;
    float& farthest = new_depth_m_[std::size_t(pixel)];
    farthest = std::max(farthest, distance_m(i));
  }
  farthest_around_3x3(new_depth_m_, width_px_, height_px_, executor, &around_depth_m_);
  executor.parallel_chunks(kept_, kChunkRays, [&](std::size_t first, std::size_t last, unsigned) {
    for (std::size_t i = first; i < last; ++i) {
      const glm::vec2 q = sample_px_[i];
      if (row_[i] < 0 || !(q.x >= 0.0f && q.y >= 0.0f && q.x < float(width) && q.y < float(height))) continue;
      const float farthest_new_m = around_depth_m_[std::size_t(q.y) * width + std::size_t(q.x)];
      if (!std::isfinite(farthest_new_m)) continue;
      if (kept_ray_covered(distance_m(i), farthest_new_m)) row_[i] = -1;
    }
  });
}

}  // namespace foveart::foveation
