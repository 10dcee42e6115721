// Laplacian pyramid of luminance and its band-limited contrast (contrast_pyramid.hpp).
//
// Every pass runs along rows: vertical passes walk whole rows (or strips of columns) at a
// time instead of one strided column, so that they stream through memory and vectorise. Each
// output value gets the arithmetic of the plain per-line filter in the same order, so that the
// result does not depend on the executor or its chunks.
#include <eval/contrast_pyramid.hpp>

#include <foveation/executor.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <numbers>

namespace foveart::eval {
namespace {

constexpr float kBinomial[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};
constexpr int kRowChunk = 8;      // rows per task
constexpr int kColumnStrip = 128;  // columns per task of a vertical running box

int clamp_index(int i, int n) { return std::clamp(i, 0, n - 1); }

// body(first, last) over [0, n) in chunks, on the executor's threads when there is one.
void chunks(foveation::Executor* ex, int n, int chunk, const std::function<void(int, int)>& body) {
  if (ex == nullptr || n <= chunk) return body(0, n);
  ex->parallel_chunks(std::size_t(n), std::size_t(chunk), [&](std::size_t a, std::size_t b, unsigned) { body(int(a), int(b)); });
}

float* row(Plane& p, int y) { return p.v.data() + std::size_t(y) * std::size_t(p.width_px); }
const float* row(const Plane& p, int y) { return p.v.data() + std::size_t(y) * std::size_t(p.width_px); }

// One row of the binomial with clamped borders: sum over k of kBinomial[k + 2] in[x + k], k ascending.
void binomial_row(const float* in, float* out, int w) {
  const auto clamped = [&](int x) {
    float s = 0.0f;
    for (int k = -2; k <= 2; ++k) s += kBinomial[k + 2] * in[clamp_index(x + k, w)];
    out[x] = s;
  };
  const int lo = std::min(2, w), hi = std::max(lo, w - 2);
  for (int x = 0; x < lo; ++x) clamped(x);
  for (int x = lo; x < hi; ++x) {
    float s = 0.0f;
    s += kBinomial[0] * in[x - 2];
    s += kBinomial[1] * in[x - 1];
    s += kBinomial[2] * in[x];
    s += kBinomial[3] * in[x + 1];
    s += kBinomial[4] * in[x + 2];
    out[x] = s;
  }
  for (int x = hi; x < w; ++x) clamped(x);
}

// Separable binomial blur with clamped borders.
Plane binomial_blur(const Plane& in, foveation::Executor* ex) {
  const int w = in.width_px, h = in.height_px;
  Plane tmp = Plane::uninitialized(w, h), out = Plane::uninitialized(w, h);
  chunks(ex, h, kRowChunk, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) binomial_row(row(in, y), row(tmp, y), w);
  });
  chunks(ex, h, kRowChunk, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const float* r[5];
      for (int k = -2; k <= 2; ++k) r[k + 2] = row(tmp, clamp_index(y + k, h));
      float* o = row(out, y);
      for (int x = 0; x < w; ++x) {
        float s = 0.0f;
        for (int k = 0; k < 5; ++k) s += kBinomial[k] * r[k][x];
        o[x] = s;
      }
    }
  });
  return out;
}

// The binomial's frequency response at f cycles per pixel: (6 + 8 cos 2 pi f + 2 cos 4 pi f) / 16.
double binomial_response(double f) {
  return (6.0 + 8.0 * std::cos(2.0 * std::numbers::pi * f) + 2.0 * std::cos(4.0 * std::numbers::pi * f)) / 16.0;
}

// One running-box pass of odd width along a row of n values; borders clamped.
void box_pass_row(float* line, int n, int radius, std::vector<float>& scratch) {
  scratch.resize(std::size_t(n));
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) sum += double(line[clamp_index(k, n)]);
  const double inv = 1.0 / double(2 * radius + 1);
  for (int i = 0; i < n; ++i) {
    scratch[std::size_t(i)] = float(sum * inv);
    sum += double(line[clamp_index(i + radius + 1, n)]) - double(line[clamp_index(i - radius, n)]);
  }
  std::copy(scratch.begin(), scratch.end(), line);
}

// The same pass down columns [x0, x1), all of them a row at a time.
using Scratch = std::vector<float, PlaneAllocator<float>>;  // a strip of columns: recycled (plane_memory)

void box_pass_columns(Plane& p, int x0, int x1, int radius, std::vector<double>& sum, Scratch& scratch) {
  const int n = p.height_px, cw = x1 - x0;
  sum.assign(std::size_t(cw), 0.0);
  scratch.resize(std::size_t(n) * std::size_t(cw));
  for (int k = -radius; k <= radius; ++k) {
    const float* r = row(p, clamp_index(k, n)) + x0;
    for (int x = 0; x < cw; ++x) sum[std::size_t(x)] += double(r[x]);
  }
  const double inv = 1.0 / double(2 * radius + 1);
  for (int i = 0; i < n; ++i) {
    float* o = scratch.data() + std::size_t(i) * std::size_t(cw);
    const float* add = row(p, clamp_index(i + radius + 1, n)) + x0;
    const float* sub = row(p, clamp_index(i - radius, n)) + x0;
    for (int x = 0; x < cw; ++x) {
      o[x] = float(sum[std::size_t(x)] * inv);
      sum[std::size_t(x)] += double(add[x]) - double(sub[x]);
    }
  }
  for (int i = 0; i < n; ++i) std::copy_n(scratch.data() + std::size_t(i) * std::size_t(cw), cw, row(p, i) + x0);
}

// Every other pixel of a blurred plane.
Plane decimate(const Plane& blurred, foveation::Executor* ex) {
  Plane out = Plane::uninitialized((blurred.width_px + 1) / 2, (blurred.height_px + 1) / 2);
  chunks(ex, out.height_px, kRowChunk, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < out.width_px; ++x) out.at(x, y) = blurred.at(2 * x, 2 * y);
  });
  return out;
}

// EXPAND along one line (expand's comment): n_in inputs `stride` apart to n_out outputs.
void expand_line(const float* src, std::size_t stride, int n_in, float* dst, int n_out) {
  for (int x = 0; x < n_out; ++x) {
    const int i = x / 2;
    const float a = src[std::size_t(clamp_index(i, n_in)) * stride];
    const float next = src[std::size_t(clamp_index(i + 1, n_in)) * stride];
    if (x % 2 == 0) {
      const float prev = src[std::size_t(clamp_index(i - 1, n_in)) * stride];
      dst[x] = 0.125f * prev + 0.75f * a + 0.125f * next;
    } else {
      dst[x] = 0.5f * (a + next);
    }
  }
}

}  // namespace

namespace plane_memory {
namespace {

constexpr std::size_t kRecycleMinFloats = std::size_t(1) << 16;  // 256 KiB: smaller blocks go to the heap
constexpr std::size_t kRecycleMaxBytes = std::size_t(1) << 29;   // 512 MiB kept at most

struct Recycler {
  std::mutex mutex;
  std::multimap<std::size_t, float*> free;  // by size in floats
  std::size_t bytes = 0;
};

Recycler& recycler() {
  static Recycler* const r = new Recycler;  // never destroyed: a plane may be freed after static destruction
  return *r;
}

}  // namespace

float* allocate(std::size_t n) {
  if (n >= kRecycleMinFloats) {
    Recycler& r = recycler();
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (const auto it = r.free.find(n); it != r.free.end()) {
      float* p = it->second;
      r.free.erase(it);
      r.bytes -= n * sizeof(float);
      return p;
    }
  }
  return static_cast<float*>(::operator new(n * sizeof(float)));
}

void deallocate(float* p, std::size_t n) noexcept {
  if (n >= kRecycleMinFloats) {
    Recycler& r = recycler();
    const std::lock_guard<std::mutex> lock(r.mutex);
    if (r.bytes + n * sizeof(float) <= kRecycleMaxBytes) {
      r.free.emplace(n, p);
      r.bytes += n * sizeof(float);
      return;
    }
  }
  ::operator delete(p);
}

}  // namespace plane_memory

Plane pyramid_reduce(const Plane& in) { return decimate(binomial_blur(in, nullptr), nullptr); }

// Burt & Adelson's EXPAND, polyphase: an even output 2i takes (1 6 1) / 8 of inputs i - 1, i, i + 1,
// an odd one 2i + 1 half of i and i + 1, input indices clamped, so that a flat plane stays flat
// to its borders (zero insertion against clamped output borders would not).
Plane pyramid_expand(const Plane& in, int width_px, int height_px, foveation::Executor* ex) {
  Plane tmp = Plane::uninitialized(width_px, in.height_px), out = Plane::uninitialized(width_px, height_px);
  chunks(ex, in.height_px, kRowChunk, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) expand_line(row(in, y), 1, in.width_px, row(tmp, y), width_px);
  });
  const int n_in = in.height_px;
  chunks(ex, height_px, kRowChunk, [&](int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
      const int i = y / 2;
      const float* a = row(tmp, clamp_index(i, n_in));
      const float* next = row(tmp, clamp_index(i + 1, n_in));
      float* o = row(out, y);
      if (y % 2 == 0) {
        const float* prev = row(tmp, clamp_index(i - 1, n_in));
        for (int x = 0; x < width_px; ++x) o[x] = 0.125f * prev[x] + 0.75f * a[x] + 0.125f * next[x];
      } else {
        for (int x = 0; x < width_px; ++x) o[x] = 0.5f * (a[x] + next[x]);
      }
    }
  });
  return out;
}

LaplacianPyramid laplacian_pyramid(const Plane& luminance, int level_count, foveation::Executor* ex) {
  LaplacianPyramid p;
  Plane g = luminance;
  for (int level = 0; level < level_count; ++level) {
    Plane once = binomial_blur(g, ex);
    Plane mean = binomial_blur(once, ex);
    Plane upper = Plane::uninitialized(g.width_px, g.height_px), lower = Plane::uninitialized(g.width_px, g.height_px);
    chunks(ex, g.height_px, kRowChunk, [&](int y0, int y1) {
      const std::size_t a = std::size_t(y0) * std::size_t(g.width_px), b = std::size_t(y1) * std::size_t(g.width_px);
      for (std::size_t i = a; i < b; ++i) {
        upper.v[i] = g.v[i] - once.v[i];
        lower.v[i] = once.v[i] - mean.v[i];
      }
    });
    p.band.push_back(std::move(upper));
    p.band.push_back(std::move(lower));
    p.mean.push_back(std::move(mean));
    if (level + 1 < level_count) g = decimate(once, ex);
  }
  return p;
}

double laplacian_band_gain(int band, double freq_cyc_px) {
  const int level = band / kBandsPerLevel;
  double lowpass = 1.0;
  for (int k = 0; k < level; ++k) lowpass *= binomial_response(std::ldexp(freq_cyc_px, k));
  const double h = binomial_response(std::ldexp(freq_cyc_px, level));
  return lowpass * (band % kBandsPerLevel == 0 ? 1.0 - h : h * (1.0 - h));
}

static int box3_radius(double sigma_px) {
  const int width = std::max(1, int(std::lround(std::sqrt(4.0 * sigma_px * sigma_px + 1.0))));
  return width / 2;
}

double box3_variance(double sigma_px) {
  if (!(sigma_px > 0.5)) return 0.0;
  const double w = 2.0 * box3_radius(sigma_px) + 1.0;
  return 3.0 * (w * w - 1.0) / 12.0;
}

void box3_blur(Plane& p, double sigma_px, foveation::Executor* ex) {
  if (!(sigma_px > 0.5)) return;
  const int radius = box3_radius(sigma_px);
  const int strips = (p.width_px + kColumnStrip - 1) / kColumnStrip;
  for (int pass = 0; pass < 3; ++pass) {
    chunks(ex, p.height_px, kRowChunk, [&](int y0, int y1) {
      std::vector<float> scratch;
      for (int y = y0; y < y1; ++y) box_pass_row(row(p, y), p.width_px, radius, scratch);
    });
    chunks(ex, strips, 1, [&](int s0, int s1) {
      std::vector<double> sum;
      Scratch scratch;
      for (int s = s0; s < s1; ++s)
        box_pass_columns(p, s * kColumnStrip, std::min(p.width_px, (s + 1) * kColumnStrip), radius, sum, scratch);
    });
  }
}

}  // namespace foveart::eval
