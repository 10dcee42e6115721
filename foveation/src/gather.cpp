#include "foveation/gather.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <thread>

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

// ---- Gather -------------------------------------------------------------------

namespace {

using v4 = float __attribute__((vector_size(16)));

inline v4 load(const Rgba& c) {
  v4 v;
  std::memcpy(&v, &c, 16);
  return v;
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
template <typename W>
void slow_pixel(const Frame& f, std::size_t cp, const W* w, float* dst, GatherStats& stats) {
  const auto& t = *f.table;
  const auto& nt = *f.nt;
  const int taps = t.taps();
  if (t.has_weights()) {
    double a = 0, s = 0;
    double acc[3] = {0, 0, 0};
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int j = 0; j < taps; ++j) {
      const float wj = weight_of(w, j);
      s += double(wj);
      const Rgba& c = f.colors[nt.neighbor(cp, j)];
      if (c.a == 0.0f) continue;
      a += double(wj);
      const float ch[3] = {c.r, c.g, c.b};
      for (int i = 0; i < 3; ++i) {
        acc[i] += double(wj) * double(ch[i]);
        lo[i] = std::min(lo[i], ch[i]);
        hi[i] = std::max(hi[i], ch[i]);
      }
    }
    if (!t.normalized()) s = double(t.weight_sum[cp]);
    const double min_fraction = t.is_rbf() ? 0.5 : 0.0;
    if (a > 0.0 && a >= min_fraction * s) {
      const double gain = t.normalized() ? 1.0 / a : s / a;
      for (int i = 0; i < 3; ++i) {
        float v = float(acc[i] * gain);
        if (t.is_rbf() && f.options->clamp_rbf) v = std::clamp(v, lo[i], hi[i]);
        dst[i] = v;
      }
      ++stats.renormalized;
      return;
    }
  }
  for (int j = 0; j < nt.k(); ++j) {  // nearest valid point within reach
    const Rgba& c = f.colors[nt.neighbor(cp, j)];
    if (c.a != 0.0f) {
      dst[0] = c.r, dst[1] = c.g, dst[2] = c.b;
      ++stats.nearest_valid;
      return;
    }
  }
  const auto& fb = f.options->fallback_rgb;
  dst[0] = fb[0], dst[1] = fb[1], dst[2] = fb[2];
  ++stats.fallback;
}

// Rows [y0, y1) of the screen. kClamp: RBF clamp to the taps' range.
template <typename W, bool kClamp>
void gather_rows(const Frame& f, const W* weights, int y0, int y1, GatherStats& stats) {
  const auto& t = *f.table;
  const int k = t.k();
  const std::size_t stride = std::size_t(f.nt->k()) * 3;
  const std::uint8_t* packed = f.nt->packed().data();
  const int w_px = f.out->width_px;
  const int ox = f.mapping->canvas_from_screen_x_px, oy = f.mapping->canvas_from_screen_y_px;
  const bool normalized = t.normalized();
  for (int y = y0; y < y1; ++y) {
    float* dst = f.out->at(0, y);
    const std::size_t row = std::size_t(y + oy) * std::size_t(t.width_px) + std::size_t(ox);
    for (int x = 0; x < w_px; ++x, dst += 3) {
      const std::size_t cp = row + std::size_t(x);
      const std::uint8_t* nb = packed + cp * stride;
      const W* w = weights + cp * std::size_t(k);
      v4 acc = {0, 0, 0, 0};
      v4 lo = {INFINITY, INFINITY, INFINITY, INFINITY};
      v4 hi = -lo;
      for (int j = 0; j < k; ++j) {
        const v4 c = load(f.colors[load24(nb + 3 * j)]);
        acc += weight_of(w, j) * c;
        lo = lo < c ? lo : c;
        if constexpr (kClamp) hi = hi > c ? hi : c;
      }
      if (lo[3] == 0.0f) {  // an invalid tap: the documented slow path
        slow_pixel(f, cp, w, dst, stats);
        continue;
      }
      if (normalized) acc *= 1.0f / acc[3];  // sum of stored weights (half rounding)
      if constexpr (kClamp) acc = acc < lo ? lo : (acc > hi ? hi : acc);
      dst[0] = acc[0], dst[1] = acc[1], dst[2] = acc[2];
    }
  }
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

void gather_band(const Frame& f, int y0, int y1, GatherStats& stats) {
  const auto& t = *f.table;
  const bool clamp = t.is_rbf() && f.options->clamp_rbf;
  if (!t.has_weights()) {
    gather_rows_nn(f, y0, y1, stats);
  } else if (t.precision == WeightPrecision::f16) {
    clamp ? gather_rows<std::uint16_t, true>(f, t.weights_f16.data(), y0, y1, stats)
          : gather_rows<std::uint16_t, false>(f, t.weights_f16.data(), y0, y1, stats);
  } else {
    clamp ? gather_rows<float, true>(f, t.weights_f32.data(), y0, y1, stats)
          : gather_rows<float, false>(f, t.weights_f32.data(), y0, y1, stats);
  }
}

}  // namespace

GatherStats gather(const NeighborTable& nt, const InterpolationTable& table, const PointColors& colors,
                   const GazeMapping& mapping, ImageRgb& out, const GatherOptions& options) {
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
  if (table.has_weights() && (table.precision == WeightPrecision::f16 ? table.weights_f16.size() : table.weights_f32.size()) !=
                                 table.pixel_count() * std::size_t(table.k())) {
    throw std::invalid_argument("gather: interpolation table has no weights for its size");
  }
  if (colors.rgba.empty()) throw std::invalid_argument("gather: no point colours");
  if (out.width_px != w || out.height_px != h || out.rgb.size() != std::size_t(w) * std::size_t(h) * 3) {
    out = ImageRgb(w, h);
  }
  const Frame f{&nt, &table, colors.rgba.data(), &mapping, &options, &out};
  int threads = options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, h);
  auto stats = std::vector<GatherStats>(std::size_t(threads));
  std::vector<std::thread> pool;
  auto band = [&](int i) { gather_band(f, h * i / threads, h * (i + 1) / threads, stats[std::size_t(i)]); };
  for (int i = 1; i < threads; ++i) pool.emplace_back(band, i);
  band(0);
  for (auto& th : pool) th.join();
  GatherStats total;
  for (const auto& s : stats) {
    total.renormalized += s.renormalized;
    total.nearest_valid += s.nearest_valid;
    total.fallback += s.fallback;
  }
  return total;
}

}  // namespace foveart::foveation
