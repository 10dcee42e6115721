// Helpers shared by the interpolation tests: brute-force k nearest samples
// ordered by (distance, index) and one-query interpolation through the weights.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "foveation/interpolation_weights.hpp"

namespace foveart::foveation::test {

// The interpolation options of a method at k neighbours.
inline InterpOptions opts(InterpMethod m, int k) {
  InterpOptions o;
  o.method = m;
  o.k = k;
  return o;
}

struct Sample {
  Vec2d p;
  double f = 0.0;
};

inline std::vector<std::uint32_t> knn(const std::vector<Sample>& s, Vec2d q, int k) {
  std::vector<std::uint32_t> idx(s.size());
  std::iota(idx.begin(), idx.end(), 0u);
  auto d2 = [&](std::uint32_t i) {
    const double dx = s[i].p.x - q.x, dy = s[i].p.y - q.y;
    return dx * dx + dy * dy;
  };
  std::partial_sort(idx.begin(), idx.begin() + k, idx.end(), [&](std::uint32_t a, std::uint32_t b) {
    const double da = d2(a), db = d2(b);
    return da < db || (da == db && a < b);
  });
  idx.resize(std::size_t(k));
  return idx;
}

struct Result {
  double value = 0.0;
  WeightInfo info;
  std::vector<double> w;
  std::vector<std::uint32_t> ids;
};

inline Result interpolate(const InterpOptions& o, const std::vector<Sample>& s, Vec2d q) {
  Result r;
  r.ids = knn(s, q, o.k);
  std::vector<Vec2d> nb;
  std::vector<double> f;
  for (auto i : r.ids) nb.push_back(s[i].p), f.push_back(s[i].f);
  r.w.resize(nb.size());
  r.info = interpolation_weights(o, nb, r.ids, q, r.w);
  r.value = apply_weights(r.w, f);
  return r;
}

// Jittered grid of n x n samples on [0, 1]^2 (spacing h = 1/n).
inline std::vector<Sample> jittered_grid(int n, double (*f)(double, double), std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.35, 0.35);
  std::vector<Sample> s;
  const double h = 1.0 / n;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const Vec2d p{(x + 0.5 + u(rng)) * h, (y + 0.5 + u(rng)) * h};
      s.push_back({p, f(p.x, p.y)});
    }
  }
  return s;
}

// Franke's test function (Franke 1982).
inline double franke(double x, double y) {
  return 0.75 * std::exp(-((9 * x - 2) * (9 * x - 2) + (9 * y - 2) * (9 * y - 2)) / 4) +
         0.75 * std::exp(-((9 * x + 1) * (9 * x + 1)) / 49 - (9 * y + 1) / 10) +
         0.5 * std::exp(-((9 * x - 7) * (9 * x - 7) + (9 * y - 3) * (9 * y - 3)) / 4) -
         0.2 * std::exp(-(9 * x - 4) * (9 * x - 4) - (9 * y - 7) * (9 * y - 7));
}

inline const InterpMethod kAllMethods[] = {InterpMethod::nearest, InterpMethod::msm, InterpMethod::rbf,
                                           InterpMethod::rbf_gauss};

}  // namespace foveart::foveation::test
