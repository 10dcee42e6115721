// Band-limited contrast (Peli 1990, "Contrast in complex images", JOSA A 7(10)) on a
// Laplacian pyramid (Burt & Adelson 1983) of luminance, with its 5-tap binomial kernel.
#pragma once

#include <vector>

namespace foveart::eval {

// One single-channel image plane, row-major.
struct Plane {
  int width_px = 0;
  int height_px = 0;
  std::vector<float> v;
  Plane() = default;
  Plane(int w, int h, float fill = 0.0f) : width_px(w), height_px(h), v(std::size_t(w) * std::size_t(h), fill) {}
  float& at(int x, int y) { return v[std::size_t(y) * std::size_t(width_px) + std::size_t(x)]; }
  float at(int x, int y) const { return v[std::size_t(y) * std::size_t(width_px) + std::size_t(x)]; }
};

// Burt & Adelson's REDUCE: binomial [1 4 6 4 1]/16 blur, then every other pixel.
Plane pyramid_reduce(const Plane& in);
// Burt & Adelson's EXPAND to (width_px, height_px): zero-insert, then 2 x the binomial blur.
Plane pyramid_expand(const Plane& in, int width_px, int height_px);

// Levels of a Laplacian pyramid: band[b] = G_b - EXPAND(G_{b+1}) and mean[b] = EXPAND(G_{b+1}),
// the local mean luminance that band b's contrast is relative to (Peli 1990 eq. 5).
struct LaplacianPyramid {
  std::vector<Plane> band;
  std::vector<Plane> mean;
};
LaplacianPyramid laplacian_pyramid(const Plane& luminance, int band_count);

// Amplitude response of band b to a sinusoid of freq_cyc_px (cycles per full-resolution pixel),
// aliasing ignored: H_b(f) (1 - h(2^b f)^2) with H_b the product of the binomial's h over levels.
double laplacian_band_gain(int band, double freq_cyc_px);

// Gaussian-like blur of a plane in place: three box passes per axis of width sqrt(4 sigma^2 + 1)
// (Wells 1986), borders clamped. sigma_px <= 0.5 leaves the plane unchanged.
void box3_blur(Plane& p, double sigma_px);

}  // namespace foveart::eval
