#include "foveation/temporal_blend.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace foveart::foveation {

namespace {

// One thread's rows of the current frame, deinterleaved into planes with the
// edge pixel repeated on both sides (x = -1 and x = w read like x = 0 and
// x = w - 1: the clamp-to-edge of the 3x3 neighbourhood without branches).
// Rows live in slot row % 3, so the three rows around y never collide.
struct RowPlanes {
  int width = 0;
  int loaded[3] = {-1, -1, -1};
  std::vector<float> data;  // [slot][channel][width + 2]

  explicit RowPlanes(int w) : width(w), data(std::size_t(9) * std::size_t(w + 2)) {}
  float* plane(int slot, int channel) { return data.data() + std::size_t(slot * 3 + channel) * std::size_t(width + 2); }
  const float* row(const ImageRgb& img, int y, int channel) {
    const int slot = y % 3;
    if (loaded[slot] != y) {
      const float* src = img.at(0, y);
      for (int i = 0; i < 3; ++i) {
        float* dst = plane(slot, i);
        for (int x = 0; x < width; ++x) dst[x + 1] = src[std::size_t(x) * 3 + std::size_t(i)];
        dst[0] = dst[1];
        dst[width + 1] = dst[width];
      }
      loaded[slot] = y;
    }
    return plane(slot, channel);
  }
};

// One row, planar in and out. Each lane is one pixel and does exactly the
// operations of the scalar definition in the same order (taps row by row,
// left to right; no FMA on x86-64), so the result is bit-identical to it.
// Written without inner loops or branches so GCC vectorises it across x.
// Mean and variance of the 3x3 box, the variance in two passes (squared
// deviations from the mean): E[c^2] - mu^2 cancels catastrophically in a flat
// box and would make the clip hinge on rounding.
struct Moments {
  float mu, var;
};
inline Moments moments(const float* __restrict a, const float* __restrict b, const float* __restrict c, int x) {
  constexpr float kTaps = 9.0f;
  float m1 = 0.0f;
  m1 += a[x]; m1 += a[x + 1]; m1 += a[x + 2];
  m1 += b[x]; m1 += b[x + 1]; m1 += b[x + 2];
  m1 += c[x]; m1 += c[x + 1]; m1 += c[x + 2];
  const float mu = m1 / kTaps;
  float s = 0.0f, d = 0.0f;
  d = a[x] - mu; s += d * d; d = a[x + 1] - mu; s += d * d; d = a[x + 2] - mu; s += d * d;
  d = b[x] - mu; s += d * d; d = b[x + 1] - mu; s += d * d; d = b[x + 2] - mu; s += d * d;
  d = c[x] - mu; s += d * d; d = c[x + 1] - mu; s += d * d; d = c[x + 2] - mu; s += d * d;
  return {mu, s / kTaps};
}
// Karis 2014: clamp to the 3x3 min/max box.
inline float clamp_to_box(float h, const float* __restrict a, const float* __restrict b, const float* __restrict c,
                          int x) {
  float lo = INFINITY, hi = -INFINITY;
  lo = std::min(lo, a[x]); hi = std::max(hi, a[x]);
  lo = std::min(lo, a[x + 1]); hi = std::max(hi, a[x + 1]);
  lo = std::min(lo, a[x + 2]); hi = std::max(hi, a[x + 2]);
  lo = std::min(lo, b[x]); hi = std::max(hi, b[x]);
  lo = std::min(lo, b[x + 1]); hi = std::max(hi, b[x + 1]);
  lo = std::min(lo, b[x + 2]); hi = std::max(hi, b[x + 2]);
  lo = std::min(lo, c[x]); hi = std::max(hi, c[x]);
  lo = std::min(lo, c[x + 1]); hi = std::max(hi, c[x + 1]);
  lo = std::min(lo, c[x + 2]); hi = std::max(hi, c[x + 2]);
  return std::min(std::max(h, lo), hi);  // = std::clamp(h, lo, hi) for lo <= hi, NaN included
}

// Rows above (a), at (b) and below (c) per channel; restrict parameters so
// GCC needs no runtime alias checks.
template <HistoryClip kConstraint>
void blend_row(const float* __restrict a0, const float* __restrict a1, const float* __restrict a2,
             const float* __restrict b0, const float* __restrict b1, const float* __restrict b2,
             const float* __restrict c0, const float* __restrict c1, const float* __restrict c2,
             const float* __restrict h0, const float* __restrict h1, const float* __restrict h2,
             float* __restrict o0, float* __restrict o1, float* __restrict o2, int w, float alpha, float gamma, float floor) {
  for (int x = 0; x < w; ++x) {
    float v0 = h0[x], v1 = h1[x], v2 = h2[x];
    if constexpr (kConstraint == HistoryClip::minmax_clamp) {
      v0 = clamp_to_box(v0, a0, b0, c0, x);
      v1 = clamp_to_box(v1, a1, b1, c1, x);
      v2 = clamp_to_box(v2, a2, b2, c2, x);
    } else {
      // Salvi 2016: clip the history towards the mean onto the box mu +- gamma sigma.
      const Moments s0 = moments(a0, b0, c0, x), s1 = moments(a1, b1, c1, x), s2 = moments(a2, b2, c2, x);
      const float mu0 = s0.mu, mu1 = s1.mu, mu2 = s2.mu;
      const float e0 = gamma * std::sqrt(s0.var) + floor;
      const float e1 = gamma * std::sqrt(s1.var) + floor;
      const float e2 = gamma * std::sqrt(s2.var) + floor;
      const float d0 = std::abs(v0 - mu0), d1 = std::abs(v1 - mu1), d2 = std::abs(v2 - mu2);
      float t = 1.0f;  // largest scale of (h - mu) that stays inside the box
      const float q0 = e0 / d0, q1 = e1 / d1, q2 = e2 / d2;
      // min(t, 1) = t as t <= 1: the same as "if (d > e) t = min(t, e / d)".
      t = std::min(t, d0 > e0 ? q0 : 1.0f);
      t = std::min(t, d1 > e1 ? q1 : 1.0f);
      t = std::min(t, d2 > e2 ? q2 : 1.0f);
      v0 = mu0 + (v0 - mu0) * t;
      v1 = mu1 + (v1 - mu1) * t;
      v2 = mu2 + (v2 - mu2) * t;
    }
    o0[x] = v0 + alpha * (b0[x + 1] - v0);
    o1[x] = v1 + alpha * (b1[x + 1] - v1);
    o2[x] = v2 + alpha * (b2[x + 1] - v2);
  }
}

#if defined(__SSE2__)
// The variance-clip row with SSE2, four pixels per step: the same IEEE
// operations per lane as blend_row<variance_clip> (min/max operands ordered as
// std::min/std::max, so NaN behaves the same), hence bit-identical.
void blend_row_variance_sse(const float* __restrict a0, const float* __restrict a1, const float* __restrict a2,
                          const float* __restrict b0, const float* __restrict b1, const float* __restrict b2,
                          const float* __restrict c0, const float* __restrict c1, const float* __restrict c2,
                          const float* __restrict h0, const float* __restrict h1, const float* __restrict h2,
                          float* __restrict o0, float* __restrict o1, float* __restrict o2, int w, float alpha,
                          float gamma, float floor) {
  const __m128 taps = _mm_set1_ps(9.0f), zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
  const __m128 eps = _mm_set1_ps(floor), va = _mm_set1_ps(alpha), vg = _mm_set1_ps(gamma);
  const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  struct Stat {
    __m128 mu, e;
  };
  auto stat = [&](const float* a, const float* b, const float* c, int x) {
    __m128 m1 = zero, s = zero;
    const float* rows[3] = {a, b, c};
    for (const float* r : rows)
      for (int dx = 0; dx < 3; ++dx) m1 = _mm_add_ps(m1, _mm_loadu_ps(r + x + dx));
    const __m128 mu = _mm_div_ps(m1, taps);
    for (const float* r : rows) {
      for (int dx = 0; dx < 3; ++dx) {
        const __m128 d = _mm_sub_ps(_mm_loadu_ps(r + x + dx), mu);
        s = _mm_add_ps(s, _mm_mul_ps(d, d));
      }
    }
    return Stat{mu, _mm_add_ps(_mm_mul_ps(vg, _mm_sqrt_ps(_mm_div_ps(s, taps))), eps)};
  };
  auto scale = [&](__m128 t, __m128 v, const Stat& s) {
    const __m128 d = _mm_and_ps(_mm_sub_ps(v, s.mu), abs_mask);
    const __m128 q = _mm_div_ps(s.e, d);
    const __m128 over = _mm_cmpgt_ps(d, s.e);
    const __m128 c = _mm_or_ps(_mm_and_ps(over, q), _mm_andnot_ps(over, one));
    return _mm_min_ps(c, t);  // std::min(t, c)
  };
  auto blend = [&](__m128 v, const Stat& s, __m128 t, const float* cur, float* out, int x) {
    const __m128 hv = _mm_add_ps(s.mu, _mm_mul_ps(_mm_sub_ps(v, s.mu), t));
    _mm_storeu_ps(out + x, _mm_add_ps(hv, _mm_mul_ps(va, _mm_sub_ps(_mm_loadu_ps(cur + x + 1), hv))));
  };
  int x = 0;
  for (; x + 4 <= w; x += 4) {
    const Stat s0 = stat(a0, b0, c0, x), s1 = stat(a1, b1, c1, x), s2 = stat(a2, b2, c2, x);
    const __m128 v0 = _mm_loadu_ps(h0 + x), v1 = _mm_loadu_ps(h1 + x), v2 = _mm_loadu_ps(h2 + x);
    __m128 t = one;
    t = scale(t, v0, s0);
    t = scale(t, v1, s1);
    t = scale(t, v2, s2);
    blend(v0, s0, t, b0, o0, x);
    blend(v1, s1, t, b1, o1, x);
    blend(v2, s2, t, b2, o2, x);
  }
  if (x < w) {  // the last 1..3 pixels
    blend_row<HistoryClip::variance_clip>(a0 + x, a1 + x, a2 + x, b0 + x, b1 + x, b2 + x, c0 + x, c1 + x, c2 + x, h0 + x,
                                          h1 + x, h2 + x, o0 + x, o1 + x, o2 + x, w - x, alpha, gamma, floor);
  }
}
#endif

// Rows [y0, y1): out = lerp(constrain(history), current, weight).
void blend_rows(const ImageRgb& cur, const ImageRgb& hist, ImageRgb& out, const TemporalOptions& o, float weight, int y0,
              int y1) {
  const int w = cur.width_px, h = cur.height_px;
  RowPlanes planes(w);
  std::vector<float> hist_row(std::size_t(w) * 3), out_row(std::size_t(w) * 3);
  const float* const hist_planes[3] = {hist_row.data(), hist_row.data() + w, hist_row.data() + 2 * w};
  float* const out_planes[3] = {out_row.data(), out_row.data() + w, out_row.data() + 2 * w};
  for (int y = y0; y < y1; ++y) {
    const int ya = std::max(y - 1, 0), yb = std::min(y + 1, h - 1);
    const float* const r0[3] = {planes.row(cur, ya, 0), planes.row(cur, ya, 1), planes.row(cur, ya, 2)};
    const float* const r1[3] = {planes.row(cur, y, 0), planes.row(cur, y, 1), planes.row(cur, y, 2)};
    const float* const r2[3] = {planes.row(cur, yb, 0), planes.row(cur, yb, 1), planes.row(cur, yb, 2)};
    const float* src = hist.at(0, y);
    for (int x = 0; x < w; ++x) {
      for (int i = 0; i < 3; ++i) hist_row[std::size_t(i) * std::size_t(w) + std::size_t(x)] = src[std::size_t(x) * 3 + std::size_t(i)];
    }
#if defined(__SSE2__)
    auto* row = o.constraint == HistoryClip::minmax_clamp ? &blend_row<HistoryClip::minmax_clamp>
                                                            : &blend_row_variance_sse;
#else
    auto* row = o.constraint == HistoryClip::minmax_clamp ? &blend_row<HistoryClip::minmax_clamp>
                                                            : &blend_row<HistoryClip::variance_clip>;
#endif
    row(r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], r2[0], r2[1], r2[2], hist_planes[0], hist_planes[1],
        hist_planes[2], out_planes[0], out_planes[1], out_planes[2], w, weight, o.variance_gamma,
        o.clip_floor);
    float* dst = out.at(0, y);
    for (int x = 0; x < w; ++x) {
      for (int i = 0; i < 3; ++i) dst[std::size_t(x) * 3 + std::size_t(i)] = out_row[std::size_t(i) * std::size_t(w) + std::size_t(x)];
    }
  }
}

}  // namespace

// Karis 2014's exponential blend with alpha per ray rather than per frame.
TemporalOptions temporal_options_for_rays(TemporalOptions options, int rays_per_point) {
  if (rays_per_point <= 1) return options;
  const double history_weight = std::pow(1.0 - double(options.current_weight), rays_per_point);
  options.current_weight = float(1.0 - history_weight);
  return options;
}

// Progressive accumulation (the mean of the frames since the reset) until it
// would weigh a frame less than the exponential blend of Karis 2014.
float temporal_frame_weight(const TemporalOptions& options, std::uint32_t frames_held) {
  if (frames_held == 0) return 1.0f;
  if (!options.mean_while_young) return options.current_weight;
  return std::max(options.current_weight, 1.0f / float(double(frames_held) + 1.0));
}

bool TemporalAccumulator::begin_frame(int width_px, int height_px, glm::vec2 gaze_px, bool saccade) {
  const bool size_changed = width_px_ != width_px || height_px_ != height_px;
  const bool jumped = valid_ && glm::distance(gaze_px, gaze_px_) > options_.reset_distance_px;
  const bool onset = saccade && !flagged_;  // the first flagged frame of a saccade or blink
  flagged_ = saccade;
  gaze_px_ = gaze_px;
  width_px_ = width_px;
  height_px_ = height_px;
  last_reset_ = !valid_ || size_changed || jumped || onset;
  valid_ = true;
  if (last_reset_) {
    ++resets_;
    frames_held_ = 0;
  }
  frames_held_ = std::min<std::uint32_t>(frames_held_ + 1, 1u << 16);
  return last_reset_;
}

void TemporalAccumulator::restart_history(const ImageRgb& current) {
  history_ = current;
  frames_held_ = 1;
}

const ImageRgb& TemporalAccumulator::accumulate(const ImageRgb& current, glm::vec2 gaze_px, Executor& executor,
                                                bool saccade) {
  if (begin_frame(current.width_px, current.height_px, gaze_px, saccade)) {
    restart_history(current);
    return history_;
  }
  blend(current, history_, nullptr, executor);
  return history_;
}

const ImageRgb& TemporalAccumulator::accumulate_reprojected(const ImageRgb& current, const ImageRgb& warped_history,
                                                            const std::vector<std::uint8_t>& valid, glm::vec2 gaze_px,
                                                            Executor& executor, bool saccade) {
  const bool reset = begin_frame(current.width_px, current.height_px, gaze_px, saccade);
  if (reset || warped_history.width_px != current.width_px || warped_history.height_px != current.height_px ||
      valid.size() != current.pixel_count()) {
    if (!reset) last_reset_ = true, ++resets_;  // nothing to blend with
    restart_history(current);
    return history_;
  }
  blend(current, warped_history, valid.data(), executor);
  return history_;
}

void TemporalAccumulator::blend(const ImageRgb& current, const ImageRgb& history, const std::uint8_t* valid,
                                Executor& executor) {
  scratch_.width_px = current.width_px;
  scratch_.height_px = current.height_px;
  scratch_.rgb.resize(current.rgb.size());
  // A few bands per thread (each band sets up its own row planes once).
  const int h = current.height_px, w = current.width_px;
  const int bands = std::max(1, std::min(h, 4 * int(executor.thread_count())));
  const float weight = frame_weight();
  executor.parallel_for(std::size_t(bands), [&](std::size_t band) {
    const int y0 = h * int(band) / bands, y1 = h * (int(band) + 1) / bands;
    blend_rows(current, history, scratch_, options_, weight, y0, y1);
    if (valid == nullptr) return;
    for (std::size_t p = std::size_t(y0) * std::size_t(w); p < std::size_t(y1) * std::size_t(w); ++p) {
      if (valid[p] == 0) std::copy_n(current.rgb.data() + p * 3, 3, scratch_.rgb.data() + p * 3);  // no history here
    }
  });
  std::swap(history_, scratch_);
}

}  // namespace foveart::foveation
