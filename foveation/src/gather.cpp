#include "foveation/gather.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "foveation/rbf_clamp.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace foveart::foveation {

// ---- Point colours ------------------------------------------------------------

namespace {

bool finite3(const float* c) { return std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]); }

}  // namespace

PointColors point_colors_from_list(std::size_t point_count, std::span<const std::uint32_t> point_index,
                                   std::span<const float> rgb) {
  if (rgb.size() != point_index.size() * 3) {
    throw std::invalid_argument("point colours: " + std::to_string(rgb.size()) + " floats for " +
                                std::to_string(point_index.size()) + " points (need 3 each)");
  }
  PointColors pc;
  pc.rgba.assign(point_count, Rgba{});
  for (std::size_t i = 0; i < point_index.size(); ++i) {
    const std::uint32_t p = point_index[i];
    if (p >= point_count) {
      throw std::invalid_argument("point colours: index " + std::to_string(p) + " at entry " + std::to_string(i) +
                                  " is not below the point count " + std::to_string(point_count));
    }
    const float* c = rgb.data() + i * 3;
    if (finite3(c)) pc.rgba[p] = Rgba{c[0], c[1], c[2], 1.0f};
  }
  pc.invalid = std::size_t(std::count_if(pc.rgba.begin(), pc.rgba.end(), [](const Rgba& c) { return c.a == 0.0f; }));
  return pc;
}

PointColors point_colors_from_all(std::span<const float> rgb, std::span<const std::uint8_t> valid) {
  if (rgb.size() % 3 != 0 || (!valid.empty() && valid.size() * 3 != rgb.size())) {
    throw std::invalid_argument("point colours: " + std::to_string(rgb.size()) + " floats and " +
                                std::to_string(valid.size()) + " validity flags do not describe the same points");
  }
  PointColors pc;
  const std::size_t n = rgb.size() / 3;
  pc.rgba.assign(n, Rgba{});
  for (std::size_t i = 0; i < n; ++i) {
    const float* c = rgb.data() + i * 3;
    if ((valid.empty() || valid[i] != 0) && finite3(c)) {
      pc.rgba[i] = Rgba{c[0], c[1], c[2], 1.0f};
    } else {
      ++pc.invalid;
    }
  }
  return pc;
}

std::string_view rbf_clamp_name(RbfClamp clamp) {
  switch (clamp) {
    case RbfClamp::off: return "off";
    case RbfClamp::taps: return "taps";
    case RbfClamp::block: return "block";
  }
  return "?";
}

std::optional<RbfClamp> parse_rbf_clamp(std::string_view name) {
  for (RbfClamp c : {RbfClamp::off, RbfClamp::taps, RbfClamp::block})
    if (name == rbf_clamp_name(c)) return c;
  return std::nullopt;
}

// ---- Gather -------------------------------------------------------------------

namespace {

using v4 = float __attribute__((vector_size(16)));

inline v4 load(const Rgba& c) {
  v4 v;
  std::memcpy(&v, &c, 16);
  return v;
}

// Lane-wise min / max (minps / maxps on x86).
inline v4 min4(v4 a, v4 b) {
#if defined(__SSE__)
  return _mm_min_ps(a, b);
#else
  return a < b ? a : b;
#endif
}
inline v4 max4(v4 a, v4 b) {
#if defined(__SSE__)
  return _mm_max_ps(a, b);
#else
  return a > b ? a : b;
#endif
}

inline std::uint32_t load24(const std::uint8_t* p) {
  std::uint32_t v = 0;
  std::memcpy(&v, p, 4);  // the table keeps one pad byte at its end
  return v & 0xFFFFFFu;
}

inline float weight_of(const float* w, int j) { return w[j]; }
inline float weight_of(const std::uint16_t* w, int j) { return half_to_float(w[j]); }

struct Frame {
  const NeighborTable* nt;
  const InterpolationTable* table;
  const Rgba* colors;
  const GazeMapping* mapping;
  const GatherOptions* options;
  ImageRgb* out;
};

// Pixel with at least one invalid tap: the documented rule, with branches.
// cp: row-major canvas pixel; w: its k stored weights (tile order).
template <typename W>
void slow_pixel(const Frame& f, std::size_t cp, const W* w, float* dst, GatherStats& stats) {
  const auto& t = *f.table;
  const auto& nt = *f.nt;
  const int taps = t.taps();
  if (t.has_weights()) {
    double a = 0, s = 0;
    double acc[3] = {0, 0, 0};
    RbfClampRange<float> range[3];  // of the valid taps, per channel
    for (int j = 0; j < taps; ++j) {
      const float wj = weight_of(w, j);
      s += double(wj);
      const Rgba& c = f.colors[nt.neighbor(cp, j)];
      if (c.a == 0.0f) continue;
      a += double(wj);
      const float ch[3] = {c.r, c.g, c.b};
      for (int i = 0; i < 3; ++i) {
        acc[i] += double(wj) * double(ch[i]);
        range[i].include(ch[i]);
      }
    }
    if (!t.normalized()) s = double(t.weight_sum[cp]);
    const double min_fraction = t.is_rbf() ? 0.5 : 0.0;
    if (a > 0.0 && a >= min_fraction * s) {
      const double gain = t.normalized() ? 1.0 / a : s / a;
      for (int i = 0; i < 3; ++i) {
        float v = float(acc[i] * gain);
        if (t.is_rbf() && f.options->rbf_clamp != RbfClamp::off) v = range[i].clamp(v);
        dst[i] = v;
      }
      ++stats.renormalized;
      return;
    }
  }
  if (const std::uint32_t nearest = nearest_valid_point(nt, cp, f.colors); nearest != kNoValidPoint) {
    const Rgba& c = f.colors[nearest];
    dst[0] = c.r, dst[1] = c.g, dst[2] = c.b;
    ++stats.nearest_valid;
    return;
  }
  const auto& fb = f.options->fallback_rgb;
  dst[0] = fb[0], dst[1] = fb[1], dst[2] = fb[2];
  ++stats.fallback;
}

void gather_rows_nn(const Frame& f, int y0, int y1, GatherStats& stats) {
  const auto& t = *f.table;
  const std::size_t stride = std::size_t(f.nt->k()) * 3;
  const std::uint8_t* packed = f.nt->packed().data();
  const int w_px = f.out->width_px;
  const int ox = f.mapping->canvas_from_screen_x_px, oy = f.mapping->canvas_from_screen_y_px;
  for (int y = y0; y < y1; ++y) {
    float* dst = f.out->at(0, y);
    const std::size_t row = std::size_t(y + oy) * std::size_t(t.width_px) + std::size_t(ox);
    for (int x = 0; x < w_px; ++x, dst += 3) {
      const std::size_t cp = row + std::size_t(x);
      const Rgba& c = f.colors[load24(packed + cp * stride)];
      if (c.a == 0.0f) {
        slow_pixel<float>(f, cp, nullptr, dst, stats);
        continue;
      }
      dst[0] = c.r, dst[1] = c.g, dst[2] = c.b;
    }
  }
}

// ---- Weighted methods through the tile-local layout (gather_layout.hpp) ----------

// One pixel whose taps are all valid, portable: Σ w_j c_j over the block's
// palette colours `pal`, renormalised by Σ w_j (the 4th lane, validity 1),
// RBF optionally clamped to the taps' range.
template <typename W, bool kClamp, int kTaps>
inline v4 pixel_portable(const Rgba* pal, const std::uint8_t* s, const W* w, int k, bool normalized) {
  const int n = kTaps > 0 ? kTaps : k;
  v4 acc0 = {0, 0, 0, 0}, acc1 = acc0;
  v4 lo = {INFINITY, INFINITY, INFINITY, INFINITY};
  v4 hi = -lo;
  int j = 0;
  for (; j + 1 < n; j += 2) {  // two chains: the adds do not wait on each other
    const v4 c0 = load(pal[s[j]]), c1 = load(pal[s[j + 1]]);
    acc0 += weight_of(w, j) * c0;
    acc1 += weight_of(w, j + 1) * c1;
    if constexpr (kClamp) {
      lo = min4(lo, c0), hi = max4(hi, c0);
      lo = min4(lo, c1), hi = max4(hi, c1);
    }
  }
  if (j < n) {
    const v4 c = load(pal[s[j]]);
    acc0 += weight_of(w, j) * c;
    if constexpr (kClamp) lo = min4(lo, c), hi = max4(hi, c);
  }
  v4 acc = acc0 + acc1;
  if (normalized) acc *= 1.0f / acc[3];  // sum of stored weights (half rounding)
  if constexpr (kClamp) acc = min4(max4(acc, lo), hi);  // as the AVX2 kernel
  return acc;
}

#if defined(__x86_64__) && defined(__GNUC__)
#include <cpuid.h>
#define FOVEART_GATHER_AVX2 1
#define FOVEART_AVX2 __attribute__((target("avx2,fma,f16c")))

// Eight weights starting at w as floats (F16C for half weights). Reads 8
// entries: the caller guarantees they exist (see gather_tiles).
FOVEART_AVX2 inline __m256 load8(const std::uint16_t* w) {
  return _mm256_cvtph_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(w)));
}
FOVEART_AVX2 inline __m256 load8(const float* w) { return _mm256_loadu_ps(w); }

// The same pixel with AVX2: two taps per 256-bit FMA (one colour in each
// 128-bit half), weights kept in registers and spread with vpermps, two
// accumulators, halves summed at the end. kTaps > 0 only (fully unrolled).
template <typename W, bool kClamp, int kTaps>
FOVEART_AVX2 inline v4 pixel_avx2(const Rgba* pal, const std::uint8_t* s, const W* w, bool normalized) {
  constexpr int kGroups = (kTaps + 7) / 8;
  __m256 wg[kGroups];
#pragma GCC unroll 4
  for (int g = 0; g < kGroups; ++g) wg[g] = load8(w + 8 * g);
  const char* base = reinterpret_cast<const char*>(pal);
  __m256 acc[4] = {_mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps(), _mm256_setzero_ps()};
  __m256 lo = _mm256_set1_ps(INFINITY), hi = _mm256_set1_ps(-INFINITY);
#pragma GCC unroll 16
  for (int j = 0; j + 1 < kTaps; j += 2) {
    const __m256 c = _mm256_loadu2_m128(reinterpret_cast<const float*>(base + std::size_t(s[j + 1]) * 16),
                                        reinterpret_cast<const float*>(base + std::size_t(s[j]) * 16));
    const int l = j % 8;
    const __m256 wv = _mm256_permutevar8x32_ps(wg[j / 8], _mm256_setr_epi32(l, l, l, l, l + 1, l + 1, l + 1, l + 1));
    acc[l / 2] = _mm256_fmadd_ps(wv, c, acc[l / 2]);  // four independent chains
    if constexpr (kClamp) lo = _mm256_min_ps(lo, c), hi = _mm256_max_ps(hi, c);
  }
  const __m256 acc8 = _mm256_add_ps(_mm256_add_ps(acc[0], acc[1]), _mm256_add_ps(acc[2], acc[3]));
  __m128 sum = _mm_add_ps(_mm256_castps256_ps128(acc8), _mm256_extractf128_ps(acc8, 1));
  __m128 lo4 = _mm_min_ps(_mm256_castps256_ps128(lo), _mm256_extractf128_ps(lo, 1));
  __m128 hi4 = _mm_max_ps(_mm256_castps256_ps128(hi), _mm256_extractf128_ps(hi, 1));
  if constexpr (kTaps % 2 == 1) {
    constexpr int j = kTaps - 1;
    const __m128 c = _mm_load_ps(reinterpret_cast<const float*>(base + std::size_t(s[j]) * 16));
    const __m128 wj = _mm256_castps256_ps128(_mm256_permutevar8x32_ps(wg[j / 8], _mm256_set1_epi32(j % 8)));
    sum = _mm_fmadd_ps(wj, c, sum);
    if constexpr (kClamp) lo4 = _mm_min_ps(lo4, c), hi4 = _mm_max_ps(hi4, c);
  }
  if (normalized) sum = _mm_div_ps(sum, _mm_shuffle_ps(sum, sum, 0xFF));  // sum of stored weights
  if constexpr (kClamp) sum = _mm_min_ps(_mm_max_ps(sum, lo4), hi4);
  v4 r;
  std::memcpy(&r, &sum, 16);
  return r;
}
#endif

// The tile kernel's target: AVX2 where the AVX2 kernel exists. Its helpers
// share it and are always inlined, so the pixel loop compiles as one function.
#if defined(FOVEART_GATHER_AVX2)
#define FOVEART_GATHER_TARGET FOVEART_AVX2
#else
#define FOVEART_GATHER_TARGET
#endif
#define FOVEART_GATHER_INLINE FOVEART_GATHER_TARGET inline __attribute__((always_inline))

// One block's palette, copied into pal: how many of its colours are invalid
// and, for RbfClamp::block, the range of the valid ones.
struct BlockPalette {
  int invalid;  // an integer count: no floating-point dependency chain
  v4 lo, hi;
};

template <RbfClamp kClamp>
FOVEART_GATHER_INLINE BlockPalette load_palette(const Rgba* colors, const std::uint32_t* ids, int size, Rgba* pal) {
  int invalid = 0;  // locals, not the result's fields: they stay in registers
  v4 lo = {INFINITY, INFINITY, INFINITY, INFINITY}, hi = -lo;
  for (int i = 0; i < size; ++i) {
    pal[i] = colors[ids[i]];
    invalid += pal[i].a == 0.0f;
    if constexpr (kClamp == RbfClamp::block) {
      const v4 c = load(pal[i]);
      lo = min4(lo, c), hi = max4(hi, c);
    }
  }
  if (kClamp == RbfClamp::block && invalid != 0) {  // rare: the range of the valid colours only
    lo = v4{INFINITY, INFINITY, INFINITY, INFINITY}, hi = -lo;
    for (int i = 0; i < size; ++i)
      if (pal[i].a != 0.0f) lo = min4(lo, load(pal[i])), hi = max4(hi, load(pal[i]));
  }
  return {invalid, lo, hi};
}

// Does the pixel with palette slots s use an invalid colour?
FOVEART_GATHER_INLINE bool uses_invalid(const Rgba* pal, const std::uint8_t* s, int k) {
  bool any_invalid = false;
  for (int j = 0; j < k; ++j) any_invalid |= pal[s[j]].a == 0.0f;
  return any_invalid;
}

// A pixel whose taps are all valid: the AVX2 kernel where its weights can be
// read in groups of 8 (avx2_fits), else the portable one; RbfClamp::block
// clamps it to the block's range.
template <typename W, RbfClamp kClamp, int kTaps, bool kAvx2>
FOVEART_GATHER_INLINE v4 valid_pixel(const Rgba* pal, const BlockPalette& palette, const std::uint8_t* s, const W* w,
                                     int k, bool normalized, bool avx2_fits) {
  constexpr bool kTapsClamp = kClamp == RbfClamp::taps;
  v4 c;
#if defined(FOVEART_GATHER_AVX2)
  if constexpr (kAvx2 && kTaps > 0) {
    c = avx2_fits ? pixel_avx2<W, kTapsClamp, kTaps>(pal, s, w, normalized)
                  : pixel_portable<W, kTapsClamp, kTaps>(pal, s, w, k, normalized);
  } else
#endif
  {
    (void)avx2_fits;
    c = pixel_portable<W, kTapsClamp, kTaps>(pal, s, w, k, normalized);
  }
  if constexpr (kClamp == RbfClamp::block) c = min4(max4(c, palette.lo), palette.hi);
  return c;
}

// Screen rows [y0, y1) of one band, tile by tile. kAvx2: the AVX2 kernel.
// kClamp: RbfClamp::taps clamps each pixel in its kernel; RbfClamp::block takes
// the range of the block's valid palette colours while copying them and clamps
// each pixel of the block to it (O(1) per pixel instead of O(k)).
template <typename W, RbfClamp kClamp, int kTaps, bool kAvx2>
FOVEART_GATHER_TARGET void gather_tiles(const Frame& f, const W* weights, int y0, int y1, GatherStats& stats) {
  const auto& t = *f.table;
  const auto& l = t.layout;
  const int k = kTaps > 0 ? kTaps : t.k();
  const bool normalized = t.normalized();
  const int ox = f.mapping->canvas_from_screen_x_px, oy = f.mapping->canvas_from_screen_y_px;
  const int cx0 = ox, cx1 = ox + f.out->width_px;  // screen rectangle on the canvas
  const int cy0 = oy + y0, cy1 = oy + y1;
  alignas(32) Rgba pal[256];
  // The AVX2 kernel reads weights in groups of 8: pixels whose last group would
  // pass the end of the table take the portable kernel.
  const std::size_t weight_count = t.pixel_count() * std::size_t(k);
  const std::size_t padded = std::size_t((k + 7) / 8 * 8);
  for (int ty = cy0 / kGatherTilePx; ty * kGatherTilePx < cy1; ++ty) {
    const int ty0 = ty * kGatherTilePx;
    const int th = std::min(kGatherTilePx, t.height_px - ty0);
    const int ry0 = std::max(cy0, ty0) - ty0, ry1 = std::min(cy1, ty0 + th) - ty0;  // rows of the tile drawn
    for (int tx = cx0 / kGatherTilePx; tx * kGatherTilePx < cx1; ++tx) {
      const int tx0 = tx * kGatherTilePx;
      const int tw = std::min(kGatherTilePx, t.width_px - tx0);
      const int rx0 = std::max(cx0, tx0) - tx0, rx1 = std::min(cx1, tx0 + tw) - tx0;
      const std::size_t tile = std::size_t(ty) * std::size_t(l.tiles_x()) + std::size_t(tx);
      const int bs = kGatherTilePx >> l.tile_level[tile];
      const int nbx = (tw + bs - 1) / bs;
      // First pixel of the tile in tile order: rows of tiles above, tiles to the left.
      const std::size_t tile_base = std::size_t(ty0) * std::size_t(t.width_px) + std::size_t(tx0) * std::size_t(th);
      for (int by = ry0 / bs * bs; by < ry1; by += bs) {
        for (int bx = rx0 / bs * bs; bx < rx1; bx += bs) {
          const std::size_t b = l.tile_first_block[tile] + std::size_t((by / bs) * nbx + bx / bs);
          const BlockPalette palette = load_palette<kClamp>(f.colors, l.palette.data() + l.block_palette[b],
                                                            int(l.block_palette[b + 1] - l.block_palette[b]), pal);
          for (int ly = std::max(by, ry0); ly < std::min(by + bs, ry1); ++ly) {
            float* dst = f.out->at(tx0 + std::max(bx, rx0) - ox, ty0 + ly - oy);
            for (int lx = std::max(bx, rx0); lx < std::min(bx + bs, rx1); ++lx, dst += 3) {
              const std::size_t ord = tile_base + std::size_t(ly * tw + lx);
              const std::uint8_t* s = l.slot.data() + ord * std::size_t(k);
              const W* w = weights + ord * std::size_t(k);
              if (palette.invalid != 0 && uses_invalid(pal, s, k)) {  // an invalid point in the block, used here
                const std::size_t cp = std::size_t(ty0 + ly) * std::size_t(t.width_px) + std::size_t(tx0 + lx);
                slow_pixel(f, cp, w, dst, stats);
                continue;
              }
              const v4 c = valid_pixel<W, kClamp, kTaps, kAvx2>(pal, palette, s, w, k, normalized,
                                                                ord * std::size_t(k) + padded <= weight_count);
              dst[0] = c[0], dst[1] = c[1], dst[2] = c[2];
            }
          }
        }
      }
    }
  }
}

template <typename W, RbfClamp kClamp, bool kAvx2>
void gather_tiles_k(const Frame& f, const W* weights, int y0, int y1, GatherStats& stats) {
  switch (f.table->k()) {  // the thesis's k values unrolled
    case 5: return gather_tiles<W, kClamp, 5, kAvx2>(f, weights, y0, y1, stats);
    case 10: return gather_tiles<W, kClamp, 10, kAvx2>(f, weights, y0, y1, stats);
    case 15: return gather_tiles<W, kClamp, 15, kAvx2>(f, weights, y0, y1, stats);
    case 20: return gather_tiles<W, kClamp, 20, kAvx2>(f, weights, y0, y1, stats);
    default: return gather_tiles<W, kClamp, 0, kAvx2>(f, weights, y0, y1, stats);
  }
}

template <typename W, bool kAvx2>
void gather_tiles_w(const Frame& f, const W* weights, int y0, int y1, GatherStats& stats) {
  switch (f.table->is_rbf() ? f.options->rbf_clamp : RbfClamp::off) {
    case RbfClamp::off: return gather_tiles_k<W, RbfClamp::off, kAvx2>(f, weights, y0, y1, stats);
    case RbfClamp::taps: return gather_tiles_k<W, RbfClamp::taps, kAvx2>(f, weights, y0, y1, stats);
    case RbfClamp::block: return gather_tiles_k<W, RbfClamp::block, kAvx2>(f, weights, y0, y1, stats);
  }
}

bool use_avx2(const GatherOptions& o) {
#if defined(FOVEART_GATHER_AVX2)
  // F16C through cpuid: clang 14's __builtin_cpu_supports does not know "f16c" (the fuzz build is clang).
  static const bool cpu = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && [] {
    unsigned eax = 0, ebx = 0, ecx = 0, edx = 0;
    return __get_cpuid(1, &eax, &ebx, &ecx, &edx) != 0 && (ecx & bit_F16C) != 0;
  }();
  return o.simd && cpu;
#else
  (void)o;
  return false;
#endif
}

// Screen rows [y0, y1) (NN), or the tile rows starting in them (weighted methods).
void gather_band(const Frame& f, int y0, int y1, GatherStats& stats) {
  const auto& t = *f.table;
  if (!t.has_weights()) return gather_rows_nn(f, y0, y1, stats);
  const bool avx2 = use_avx2(*f.options);
  if (t.precision == WeightPrecision::f16) {
    const auto* w = t.weights_f16.data();
    avx2 ? gather_tiles_w<std::uint16_t, true>(f, w, y0, y1, stats)
         : gather_tiles_w<std::uint16_t, false>(f, w, y0, y1, stats);
  } else {
    const auto* w = t.weights_f32.data();
    avx2 ? gather_tiles_w<float, true>(f, w, y0, y1, stats) : gather_tiles_w<float, false>(f, w, y0, y1, stats);
  }
}

}  // namespace

GatherStats gather(const NeighborTable& nt, const InterpolationTable& table, const PointColors& colors,
                   const GazeMapping& mapping, ImageRgb& out, Executor& executor, const GatherOptions& options) {
  if (nt.width_px() != table.width_px || nt.height_px() != table.height_px || table.k() > nt.k()) {
    throw std::invalid_argument("gather: interpolation table (" + std::to_string(table.width_px) + "x" +
                                std::to_string(table.height_px) + ", k " + std::to_string(table.k()) +
                                ") does not belong to the neighbour table (" + std::to_string(nt.width_px()) + "x" +
                                std::to_string(nt.height_px()) + ", k " + std::to_string(nt.k()) + ")");
  }
  const int w = mapping.screen_width_px, h = mapping.screen_height_px;
  const int ox = mapping.canvas_from_screen_x_px, oy = mapping.canvas_from_screen_y_px;
  if (w <= 0 || h <= 0 || ox < 0 || oy < 0 || ox + w > table.width_px || oy + h > table.height_px) {
    throw std::invalid_argument("gather: screen " + std::to_string(w) + "x" + std::to_string(h) + " at canvas offset (" +
                                std::to_string(ox) + ", " + std::to_string(oy) + ") leaves the canvas " +
                                std::to_string(table.width_px) + "x" + std::to_string(table.height_px));
  }
  if (table.has_weights() && ((table.precision == WeightPrecision::f16 ? table.weights_f16.size()
                                                                        : table.weights_f32.size()) !=
                                   table.pixel_count() * std::size_t(table.k()) ||
                               table.layout.width_px != table.width_px || table.layout.height_px != table.height_px ||
                               table.layout.k != table.k() || table.layout.slot.size() != table.pixel_count() * std::size_t(table.k()))) {
    throw std::invalid_argument("gather: interpolation table has no weights or gather layout for its size");
  }
  if (colors.rgba.empty()) throw std::invalid_argument("gather: no point colours");
  if (out.width_px != w || out.height_px != h || out.rgb.size() != std::size_t(w) * std::size_t(h) * 3) {
    out = ImageRgb(w, h);
  }
  const Frame f{&nt, &table, colors.rgba.data(), &mapping, &options, &out};
  // Bands of whole tile rows (a band draws whole tiles), a few per thread so
  // the dense fovea does not hold one thread alone; same bits for any split.
  const int bands = std::min(h, 4 * int(executor.thread_count()));
  auto split = [&](int i) {
    if (i == 0 || i == bands || !table.has_weights()) return h * i / bands;
    const int rows = (oy + h - 1) / kGatherTilePx - oy / kGatherTilePx + 1;  // tile rows on the screen
    return std::clamp((oy / kGatherTilePx + rows * i / bands) * kGatherTilePx - oy, 0, h);
  };
  auto stats = std::vector<GatherStats>(executor.thread_count());  // per worker slot
  executor.parallel_for(std::size_t(bands), [&](std::size_t i, unsigned worker) {
    gather_band(f, split(int(i)), split(int(i) + 1), stats[worker]);
  });
  GatherStats total;
  for (const auto& s : stats) {
    total.renormalized += s.renormalized;
    total.nearest_valid += s.nearest_valid;
    total.fallback += s.fallback;
  }
  return total;
}

}  // namespace foveart::foveation
