// Band-limited contrast (Peli 1990, "Contrast in complex images", JOSA A 7(10)) on a
// Laplacian pyramid (Burt & Adelson 1983) of luminance, with its 5-tap binomial kernel.
#pragma once

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace foveart::foveation {
class Executor;
}

namespace foveart::eval {

// Memory of large planes, recycled: a block freed is kept (up to a cap, process-wide) for the next
// plane of the same size. A FOVE eye's evaluation makes two dozen 7 MB planes; fresh ones cost
// page faults and zeroing beyond the metric's own arithmetic, and a price list evaluates many.
namespace plane_memory {
float* allocate(std::size_t n);
void deallocate(float* p, std::size_t n) noexcept;
}  // namespace plane_memory

// A plane's allocator: plane_memory, and elements left uninitialised on resize (Plane::uninitialized).
template <class T>
struct PlaneAllocator {
  static_assert(std::is_same_v<T, float>);
  using value_type = T;
  PlaneAllocator() = default;
  T* allocate(std::size_t n) { return plane_memory::allocate(n); }
  void deallocate(T* p, std::size_t n) noexcept { plane_memory::deallocate(p, n); }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
  friend bool operator==(const PlaneAllocator&, const PlaneAllocator&) { return true; }
};

// One single-channel image plane, row-major.
struct Plane {
  int width_px = 0;
  int height_px = 0;
  std::vector<float, PlaneAllocator<float>> v;
  Plane() = default;
  Plane(int w, int h, float fill = 0.0f) : width_px(w), height_px(h), v(std::size_t(w) * std::size_t(h), fill) {}
  // For a pass that writes every value.
  static Plane uninitialized(int w, int h) {
    Plane p;
    p.width_px = w, p.height_px = h;
    p.v.resize(std::size_t(w) * std::size_t(h));
    return p;
  }
  float& at(int x, int y) { return v[std::size_t(y) * std::size_t(width_px) + std::size_t(x)]; }
  float at(int x, int y) const { return v[std::size_t(y) * std::size_t(width_px) + std::size_t(x)]; }
};

// Burt & Adelson's REDUCE: binomial [1 4 6 4 1]/16 blur, then every other pixel.
Plane pyramid_reduce(const Plane& in);
// Burt & Adelson's EXPAND to (width_px, height_px): zero-insert, then 2 x the binomial blur.
// `ex` (may be null; here and below) runs rows or column strips in parallel, same result either way.
Plane pyramid_expand(const Plane& in, int width_px, int height_px, foveation::Executor* ex = nullptr);

// Half-octave bands of a Laplacian pyramid, without its aliasing (Peli 1990's band-limited
// contrast). Level l holds G_l (G_0 the luminance, G_{l+1} = REDUCE(G_l)) and two bands at its
// resolution: band[2l] = G_l - h(G_l) and band[2l + 1] = h(G_l) - h(h(G_l)), h the binomial blur,
// half an octave apart; mean[l] = h(h(G_l)), the local mean luminance that both bands' contrast is
// relative to (Peli 1990 eq. 5). h(h(.)) is the filter EXPAND(REDUCE(.)) applies, without the
// decimation: Burt & Adelson's G_l - EXPAND(G_{l+1}) reconstructs exactly but aliases (a sinusoid
// at 1/4 cycle per pixel lands on level l + 1's Nyquist and its band energy depends on its phase).
// Octave bands are too coarse for a CSF that falls tenfold within an octave: half-octave ones let
// a band-weighting follow it (perceptual_metric.cpp).
inline constexpr int kBandsPerLevel = 2;
struct LaplacianPyramid {
  std::vector<Plane> band;  // kBandsPerLevel per level
  std::vector<Plane> mean;  // one per level
};
LaplacianPyramid laplacian_pyramid(const Plane& luminance, int level_count, foveation::Executor* ex = nullptr);

// Amplitude response of band b (level b / 2) to a sinusoid of freq_cyc_px (cycles per full-resolution
// pixel): H_l(f) (1 - h(2^l f)) or H_l(f) h(2^l f) (1 - h(2^l f)), H_l the product of the binomial's
// response h over the levels above; the decimations' aliasing is ignored.
double laplacian_band_gain(int band, double freq_cyc_px);

// Gaussian-like blur of a plane in place: three box passes per axis of width sqrt(4 sigma^2 + 1)
// (Wells 1986), borders clamped. sigma_px <= 0.5 leaves the plane unchanged.
void box3_blur(Plane& p, double sigma_px, foveation::Executor* ex = nullptr);
// The variance (pixels^2) of the blur box3_blur(p, sigma_px) applies: 3 (w^2 - 1) / 12 for its odd
// box width w; 0 where it leaves the plane unchanged.
double box3_variance(double sigma_px);

}  // namespace foveart::eval
