// Laplacian pyramid of luminance and its band-limited contrast (contrast_pyramid.hpp).
#include <eval/contrast_pyramid.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace foveart::eval {
namespace {

constexpr float kBinomial[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};

int clamp_index(int i, int n) { return std::clamp(i, 0, n - 1); }

// Separable binomial blur with clamped borders.
Plane binomial_blur(const Plane& in) {
  Plane tmp(in.width_px, in.height_px), out(in.width_px, in.height_px);
  for (int y = 0; y < in.height_px; ++y)
    for (int x = 0; x < in.width_px; ++x) {
      float s = 0.0f;
      for (int k = -2; k <= 2; ++k) s += kBinomial[k + 2] * in.at(clamp_index(x + k, in.width_px), y);
      tmp.at(x, y) = s;
    }
  for (int y = 0; y < in.height_px; ++y)
    for (int x = 0; x < in.width_px; ++x) {
      float s = 0.0f;
      for (int k = -2; k <= 2; ++k) s += kBinomial[k + 2] * tmp.at(x, clamp_index(y + k, in.height_px));
      out.at(x, y) = s;
    }
  return out;
}

// The binomial's frequency response at f cycles per pixel: (6 + 8 cos 2 pi f + 2 cos 4 pi f) / 16.
double binomial_response(double f) {
  return (6.0 + 8.0 * std::cos(2.0 * std::numbers::pi * f) + 2.0 * std::cos(4.0 * std::numbers::pi * f)) / 16.0;
}

// One running-box pass of odd width along a line of n values, stride apart; borders clamped.
void box_pass(float* line, int n, std::size_t stride, int radius, std::vector<float>& scratch) {
  scratch.resize(std::size_t(n));
  double sum = 0.0;
  for (int k = -radius; k <= radius; ++k) sum += double(line[std::size_t(clamp_index(k, n)) * stride]);
  const double inv = 1.0 / double(2 * radius + 1);
  for (int i = 0; i < n; ++i) {
    scratch[std::size_t(i)] = float(sum * inv);
    sum += double(line[std::size_t(clamp_index(i + radius + 1, n)) * stride]) -
           double(line[std::size_t(clamp_index(i - radius, n)) * stride]);
  }
  for (int i = 0; i < n; ++i) line[std::size_t(i) * stride] = scratch[std::size_t(i)];
}

}  // namespace

namespace {

// Every other pixel of a blurred plane.
Plane decimate(const Plane& blurred) {
  Plane out((blurred.width_px + 1) / 2, (blurred.height_px + 1) / 2);
  for (int y = 0; y < out.height_px; ++y)
    for (int x = 0; x < out.width_px; ++x) out.at(x, y) = blurred.at(2 * x, 2 * y);
  return out;
}

}  // namespace

Plane pyramid_reduce(const Plane& in) { return decimate(binomial_blur(in)); }

// Burt & Adelson's EXPAND, polyphase: an even output 2i takes (1 6 1) / 8 of inputs i - 1, i, i + 1,
// an odd one 2i + 1 half of i and i + 1, input indices clamped, so that a flat plane stays flat
// to its borders (zero insertion against clamped output borders would not).
Plane pyramid_expand(const Plane& in, int width_px, int height_px) {
  const auto expand_line = [](const float* src, std::size_t stride, int n_in, float* dst, std::size_t dst_stride, int n_out) {
    for (int x = 0; x < n_out; ++x) {
      const int i = x / 2;
      const float a = src[std::size_t(clamp_index(i, n_in)) * stride];
      const float next = src[std::size_t(clamp_index(i + 1, n_in)) * stride];
      if (x % 2 == 0) {
        const float prev = src[std::size_t(clamp_index(i - 1, n_in)) * stride];
        dst[std::size_t(x) * dst_stride] = 0.125f * prev + 0.75f * a + 0.125f * next;
      } else {
        dst[std::size_t(x) * dst_stride] = 0.5f * (a + next);
      }
    }
  };
  Plane tmp(width_px, in.height_px), out(width_px, height_px);
  for (int y = 0; y < in.height_px; ++y) expand_line(&in.v[std::size_t(y) * std::size_t(in.width_px)], 1, in.width_px, &tmp.at(0, y), 1, width_px);
  for (int x = 0; x < width_px; ++x)
    expand_line(&tmp.v[std::size_t(x)], std::size_t(width_px), in.height_px, &out.at(x, 0), std::size_t(width_px), height_px);
  return out;
}

LaplacianPyramid laplacian_pyramid(const Plane& luminance, int level_count) {
  LaplacianPyramid p;
  Plane g = luminance;
  for (int level = 0; level < level_count; ++level) {
    Plane once = binomial_blur(g);
    Plane mean = binomial_blur(once);
    Plane upper(g.width_px, g.height_px), lower(g.width_px, g.height_px);
    for (std::size_t i = 0; i < g.v.size(); ++i) {
      upper.v[i] = g.v[i] - once.v[i];
      lower.v[i] = once.v[i] - mean.v[i];
    }
    p.band.push_back(std::move(upper));
    p.band.push_back(std::move(lower));
    p.mean.push_back(std::move(mean));
    if (level + 1 < level_count) g = decimate(once);
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

void box3_blur(Plane& p, double sigma_px) {
  if (!(sigma_px > 0.5)) return;
  const int radius = box3_radius(sigma_px);
  std::vector<float> scratch;
  for (int pass = 0; pass < 3; ++pass) {
    for (int y = 0; y < p.height_px; ++y) box_pass(&p.at(0, y), p.width_px, 1, radius, scratch);
    for (int x = 0; x < p.width_px; ++x) box_pass(&p.at(x, 0), p.height_px, std::size_t(p.width_px), radius, scratch);
  }
}

}  // namespace foveart::eval
