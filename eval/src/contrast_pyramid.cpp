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

Plane pyramid_reduce(const Plane& in) {
  const Plane blurred = binomial_blur(in);
  Plane out((in.width_px + 1) / 2, (in.height_px + 1) / 2);
  for (int y = 0; y < out.height_px; ++y)
    for (int x = 0; x < out.width_px; ++x) out.at(x, y) = blurred.at(2 * x, 2 * y);
  return out;
}

Plane pyramid_expand(const Plane& in, int width_px, int height_px) {
  Plane up(width_px, height_px);
  for (int y = 0; y < height_px; y += 2)
    for (int x = 0; x < width_px; x += 2) up.at(x, y) = 4.0f * in.at(x / 2, y / 2);
  return binomial_blur(up);
}

LaplacianPyramid laplacian_pyramid(const Plane& luminance, int band_count) {
  LaplacianPyramid p;
  Plane g = luminance;
  for (int b = 0; b < band_count; ++b) {
    Plane next = pyramid_reduce(g);
    Plane mean = pyramid_expand(next, g.width_px, g.height_px);
    Plane band(g.width_px, g.height_px);
    for (std::size_t i = 0; i < band.v.size(); ++i) band.v[i] = g.v[i] - mean.v[i];
    p.band.push_back(std::move(band));
    p.mean.push_back(std::move(mean));
    g = std::move(next);
  }
  return p;
}

double laplacian_band_gain(int band, double freq_cyc_px) {
  double lowpass = 1.0;
  for (int k = 0; k < band; ++k) lowpass *= binomial_response(std::ldexp(freq_cyc_px, k));
  const double h = binomial_response(std::ldexp(freq_cyc_px, band));
  return lowpass * (1.0 - h * h);
}

void box3_blur(Plane& p, double sigma_px) {
  if (!(sigma_px > 0.5)) return;
  const int width = std::max(1, int(std::lround(std::sqrt(4.0 * sigma_px * sigma_px + 1.0))));
  const int radius = width / 2;
  std::vector<float> scratch;
  for (int pass = 0; pass < 3; ++pass) {
    for (int y = 0; y < p.height_px; ++y) box_pass(&p.at(0, y), p.width_px, 1, radius, scratch);
    for (int x = 0; x < p.width_px; ++x) box_pass(&p.at(x, 0), p.height_px, std::size_t(p.width_px), radius, scratch);
  }
}

}  // namespace foveart::eval
