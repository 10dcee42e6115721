// Hard cases of the one-query weights: constants, exactness, ties,
// equidistant lattices, float safety, scale invariance, RBF conditioning.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "foveation/interpolation_weights.hpp"
#include "interpolation_test_util.hpp"

namespace foveart::foveation {
namespace {

using test::Sample;

double constant_one(double, double) { return 1.0; }
double ramp(double x, double y) { return 0.3 * x + 0.7 * y; }

using test::opts;

TEST(InterpolationWeights, ParsesMethodNames) {
  for (auto m : test::kAllMethods) EXPECT_EQ(parse_method(method_name(m)), m);
  EXPECT_FALSE(parse_method("cubic").has_value());
}

TEST(InterpolationWeights, EveryMethodReproducesConstants) {
  const auto s = test::jittered_grid(12, constant_one, 7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.1, 0.9);
  for (auto m : test::kAllMethods) {
    for (int k : {1, 5, 10, 20}) {
      for (int i = 0; i < 50; ++i) {
        const auto r = test::interpolate(opts(m, k), s, {u(rng), u(rng)});
        EXPECT_NEAR(r.value, 1.0, 1e-6) << method_name(m) << " k=" << k;
      }
    }
  }
}

TEST(InterpolationWeights, ThesisPlainRbfDoesNotReproduceConstants) {
  // Thesis section 6.4: plain multiquadric RBF darkened the periphery at k = 5.
  const auto s = test::jittered_grid(12, constant_one, 7);
  for (auto m : {InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    auto o = opts(m, 5);
    o.constant_term = false;
    double worst = 0.0;
    for (int i = 0; i < 40; ++i) {
      const double t = 0.2 + 0.015 * i;
      worst = std::max(worst, std::abs(test::interpolate(o, s, {t, 1.0 - t}).value - 1.0));
    }
    EXPECT_GT(worst, 1e-3) << method_name(m);
  }
}

TEST(InterpolationWeights, QueryOnSampleReturnsIt) {
  auto s = test::jittered_grid(10, test::franke, 11);
  for (auto m : test::kAllMethods) {
    for (int k : {1, 5, 20}) {
      for (std::size_t i = 0; i < s.size(); i += 7) {
        const auto r = test::interpolate(opts(m, k), s, s[i].p);
        EXPECT_EQ(r.value, s[i].f) << method_name(m);
        EXPECT_EQ(r.info.status, WeightStatus::exact);
      }
    }
  }
}

TEST(InterpolationWeights, NearestNeighbourTiesGoToLowestIndex) {
  // Four samples at the corners of a unit square, listed in scrambled index order.
  std::vector<Sample> s = {{{1, 1}, 3.0}, {{0, 0}, 0.0}, {{1, 0}, 1.0}, {{0, 1}, 2.0}};
  for (int k : {1, 2, 4}) {
    const auto r = test::interpolate(opts(InterpMethod::nearest, k), s, {0.5, 0.5});
    EXPECT_EQ(r.value, 3.0);  // index 0 is the lowest index, all four tie
    EXPECT_EQ(r.ids[0], 0u);
  }
  // Tie between indices 1 and 2 only.
  const auto r = test::interpolate(opts(InterpMethod::nearest, 4), s, {0.5, -0.25});
  EXPECT_EQ(r.value, 0.0);
}

TEST(InterpolationWeights, MsmExactAtZeroAndTinyDistance) {
  std::vector<Vec2d> nb = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 2}};
  std::vector<double> w(nb.size());
  auto info = interpolation_weights(opts(InterpMethod::msm, 5), nb, {0, 0}, w);
  EXPECT_EQ(info.status, WeightStatus::exact);
  EXPECT_EQ(w[0], 1.0);
  info = interpolation_weights(opts(InterpMethod::msm, 5), nb, {1e-30, 0}, w);
  EXPECT_EQ(info.status, WeightStatus::ok);
  EXPECT_NEAR(w[0], 1.0, 1e-15);
  for (double x : w) EXPECT_TRUE(std::isfinite(x));
}

TEST(InterpolationWeights, MsmEquidistantLatticeIsTheMean) {
  // Pixel centre in the middle of a lattice cell: four equidistant neighbours.
  std::vector<Vec2d> nb = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  std::vector<double> w(4);
  const auto info = interpolation_weights(opts(InterpMethod::msm, 4), nb, {0.5, 0.5}, w);
  EXPECT_EQ(info.status, WeightStatus::equidistant);
  for (double x : w) EXPECT_EQ(x, 0.25);
  // Same result run twice (determinism).
  std::vector<double> w2(4);
  interpolation_weights(opts(InterpMethod::msm, 4), nb, {0.5, 0.5}, w2);
  EXPECT_EQ(w, w2);
}

TEST(InterpolationWeights, MsmWeightsNonNegativeInFloat) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) {
    const float radius = std::ldexp(u(rng) + 0.5f, int(u(rng) * 60.0f) - 30);
    const float h_min = radius * u(rng) + std::numeric_limits<float>::denorm_min();
    // h slightly beyond R (rounding of the farthest distance) must not go negative.
    const float h = std::max(h_min, radius * (1.0f + (u(rng) - 0.5f) * 1e-6f));
    const float w = msm_weight(h, h_min, radius);
    ASSERT_GE(w, 0.0f);
    ASSERT_TRUE(std::isfinite(w));
  }
}

TEST(InterpolationWeights, MsmStaysWithinNeighbourRange) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Sample> s;
  for (int i = 0; i < 300; ++i) s.push_back({{u(rng), u(rng)}, u(rng) * 10.0 - 5.0});
  for (int k : {2, 5, 20}) {
    for (int i = 0; i < 300; ++i) {
      const auto r = test::interpolate(opts(InterpMethod::msm, k), s, {u(rng), u(rng)});
      double lo = INFINITY, hi = -INFINITY;
      for (auto id : r.ids) lo = std::min(lo, s[id].f), hi = std::max(hi, s[id].f);
      EXPECT_GE(r.value, lo - 1e-12 * std::abs(lo));
      EXPECT_LE(r.value, hi + 1e-12 * std::abs(hi));
      for (double w : r.w) EXPECT_GE(w, 0.0);
    }
  }
}

TEST(InterpolationWeights, ScaleInvariance) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto m : test::kAllMethods) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<Vec2d> nb(10);
      for (auto& p : nb) p = {u(rng), u(rng)};
      const Vec2d q{u(rng), u(rng)};
      std::vector<double> w(10), ws(10);
      const auto base = interpolation_weights(opts(m, 10), nb, q, w);
      for (double scale : {1e-3, 1e3}) {
        std::vector<Vec2d> nbs = nb;
        for (auto& p : nbs) p = {p.x * scale, p.y * scale};
        const auto scaled = interpolation_weights(opts(m, 10), nbs, {q.x * scale, q.y * scale}, ws);
        EXPECT_EQ(scaled.status, base.status);
        double wmax = 1.0;
        for (double x : w) wmax = std::max(wmax, std::abs(x));
        for (int i = 0; i < 10; ++i) EXPECT_NEAR(ws[std::size_t(i)], w[std::size_t(i)], 1e-7 * wmax) << method_name(m);
      }
    }
  }
}

TEST(InterpolationWeights, RbfShapeSweepResiduals) {
  const auto s = test::jittered_grid(16, test::franke, 21);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0.15, 0.85);
  for (auto m : {InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    for (int k : {5, 10, 20}) {
      for (double shape : {0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0}) {
        auto o = opts(m, k);
        o.shape = shape;
        int solved = 0;
        for (int i = 0; i < 20; ++i) {
          const auto r = test::interpolate(o, s, {u(rng), u(rng)});
          ASSERT_TRUE(std::isfinite(r.value));
          if (r.info.status == WeightStatus::ok) {
            ++solved;
            EXPECT_LE(r.info.residual, o.residual_max);
            EXPECT_GE(r.info.rcond, o.rcond_min);
          }
          double sum = 0;
          for (double w : r.w) sum += w;
          EXPECT_NEAR(sum, 1.0, 1e-6);  // with the constant term, or MSM fallback
        }
        // Well-conditioned shapes must actually be solved, not fall back.
        if (shape >= 0.5 && !(m == InterpMethod::rbf_gauss && shape < 1.0)) {
          EXPECT_EQ(solved, 20) << shape;
        }
      }
    }
  }
}

TEST(InterpolationWeights, RbfNearDuplicatesAreMerged) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  for (auto m : {InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    std::vector<Vec2d> nb(10);
    for (auto& p : nb) p = {u(rng), u(rng)};
    nb[3] = {nb[1].x + 3e-7, nb[1].y - 2e-7};  // < 1e-6 px apart
    nb[7] = nb[2];                            // exact duplicate
    std::vector<double> w(10);
    const auto info = interpolation_weights(opts(m, 10), nb, {5.0, 5.0}, w);
    EXPECT_EQ(info.status, WeightStatus::ok);
    EXPECT_EQ(info.merged, 2);
    EXPECT_EQ(w[3], 0.0);
    EXPECT_EQ(w[7], 0.0);
    double sum = 0;
    for (double x : w) {
      sum += x;
      EXPECT_TRUE(std::isfinite(x));
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
}

TEST(InterpolationWeights, RbfCollinearNeighbourhood) {
  std::vector<Sample> s;
  for (int i = 0; i < 20; ++i) s.push_back({{i * 1.0, 2.0 * i}, ramp(i * 1.0, 2.0 * i)});
  for (auto m : {InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    for (const Vec2d q : {Vec2d{4.5, 9.0}, Vec2d{4.5, 11.0}, Vec2d{30.0, 0.0}}) {
      const auto r = test::interpolate(opts(m, 10), s, q);
      EXPECT_TRUE(r.info.collinear);
      ASSERT_TRUE(std::isfinite(r.value));
      double lo = INFINITY, hi = -INFINITY;
      for (auto id : r.ids) lo = std::min(lo, s[id].f), hi = std::max(hi, s[id].f);
      const double span = hi - lo;
      EXPECT_GE(r.value, lo - 0.5 * span);
      EXPECT_LE(r.value, hi + 0.5 * span);
    }
    // On the line between samples the ramp is reproduced closely.
    const auto r = test::interpolate(opts(m, 10), s, {4.5, 9.0});
    EXPECT_NEAR(r.value, ramp(4.5, 9.0), 0.02 * ramp(4.5, 9.0));
  }
}

TEST(InterpolationWeights, RbfReproducesRampWell) {
  const auto s = test::jittered_grid(16, ramp, 31);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(0.2, 0.8);
  for (auto m : {InterpMethod::rbf, InterpMethod::rbf_gauss}) {
    double worst = 0, worst_msm = 0;
    for (int i = 0; i < 200; ++i) {
      const Vec2d q{u(rng), u(rng)};
      worst = std::max(worst, std::abs(test::interpolate(opts(m, 10), s, q).value - ramp(q.x, q.y)));
      worst_msm = std::max(worst_msm, std::abs(test::interpolate(opts(InterpMethod::msm, 10), s, q).value - ramp(q.x, q.y)));
    }
    EXPECT_LT(worst, 2e-3) << method_name(m);  // ramp range is 1
    EXPECT_LT(worst, 0.25 * worst_msm) << method_name(m);
  }
}

TEST(InterpolationWeights, StepEdgeOvershootIsBounded) {
  // Step 0 | 1 across x = 0.5 on a jittered grid; Gibbs-like overshoot of the
  // smooth RBF interpolants is measured and bounded, MSM/NN have none.
  const auto s = test::jittered_grid(16, [](double x, double) { return x < 0.5 ? 0.0 : 1.0; }, 41);
  for (auto m : test::kAllMethods) {
    for (int k : {5, 10, 20}) {
      double lo = 0, hi = 1;
      for (int i = 0; i <= 60; ++i) {
        for (int j = 0; j <= 10; ++j) {
          const double v = test::interpolate(opts(m, k), s, {0.3 + 0.4 * i / 60.0, 0.3 + 0.04 * j}).value;
          lo = std::min(lo, v), hi = std::max(hi, v);
        }
      }
      const double overshoot = std::max(-lo, hi - 1.0);
      if (m == InterpMethod::nearest || m == InterpMethod::msm) {
        EXPECT_LE(overshoot, 1e-12);  // convex weights: rounding only
      } else {
        // Measured 0.35-0.65 (docs/interpolation.md); the gather clamps to the taps' range.
        EXPECT_LT(overshoot, 0.75) << method_name(m) << " k=" << k;
        EXPECT_GT(overshoot, 0.0) << method_name(m) << " k=" << k;
      }
      RecordProperty(std::string(method_name(m)) + "_k" + std::to_string(k) + "_overshoot", std::to_string(overshoot));
    }
  }
}

double rms_error(InterpMethod m, int k, int n) {
  const auto s = test::jittered_grid(n, test::franke, 100u + std::uint32_t(n));
  double e2 = 0;
  int count = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 20; ++x) {
      const Vec2d q{0.1 + 0.8 * (x + 0.5) / 20.0, 0.1 + 0.8 * (y + 0.5) / 20.0};
      const double d = test::interpolate(opts(m, k), s, q).value - test::franke(q.x, q.y);
      e2 += d * d, ++count;
    }
  }
  return std::sqrt(e2 / count);
}

TEST(InterpolationWeights, FrankeConvergenceSlope) {
  // Error against spacing h = 1/n on a log-log scale. Shepard-type weights
  // reproduce constants only: first order. RBF with a constant term on local
  // stencils converges faster (>= second order before saturating).
  struct Expect { InterpMethod m; int k; double min_slope; };
  for (const auto& e : {Expect{InterpMethod::nearest, 1, 0.8}, Expect{InterpMethod::msm, 10, 0.9},
                        Expect{InterpMethod::rbf, 20, 1.8}, Expect{InterpMethod::rbf_gauss, 20, 1.8}}) {
    const double e1 = rms_error(e.m, e.k, 16), e2 = rms_error(e.m, e.k, 32), e3 = rms_error(e.m, e.k, 64);
    const double slope = std::log(e1 / e3) / std::log(4.0);
    RecordProperty(std::string(method_name(e.m)) + "_slope", std::to_string(slope));
    std::printf("%s k=%d rms %.3g %.3g %.3g slope %.2f\n", std::string(method_name(e.m)).c_str(), e.k, e1, e2, e3, slope);
    EXPECT_GT(slope, e.min_slope) << method_name(e.m);
    EXPECT_LT(e3, e2);
    EXPECT_LT(e2, e1);
  }
}

TEST(InterpolationWeights, NoNonFiniteOutputForHardInputs) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::vector<Sample>> sets;
  {  // lattice with exact ties
    std::vector<Sample> s;
    for (int y = 0; y < 6; ++y) for (int x = 0; x < 6; ++x) s.push_back({{double(x), double(y)}, u(rng)});
    sets.push_back(s);
  }
  {  // coordinates near 1e6 with sub-pixel spacing
    std::vector<Sample> s;
    for (int i = 0; i < 40; ++i) s.push_back({{1e6 + u(rng), 1e6 + u(rng)}, u(rng)});
    sets.push_back(s);
  }
  {  // duplicates and near-duplicates
    std::vector<Sample> s;
    for (int i = 0; i < 10; ++i) s.push_back({{0.0, 0.0}, u(rng)});
    for (int i = 0; i < 10; ++i) s.push_back({{1e-9 * i, 1.0}, u(rng)});
    sets.push_back(s);
  }
  {  // collinear
    std::vector<Sample> s;
    for (int i = 0; i < 25; ++i) s.push_back({{double(i), 0.0}, u(rng)});
    sets.push_back(s);
  }
  for (const auto& s : sets) {
    for (auto m : test::kAllMethods) {
      for (int k : {1, 2, 5, 20}) {
        for (bool constant : {true, false}) {
          auto o = opts(m, k);
          o.constant_term = constant;
          for (int i = 0; i < 30; ++i) {
            const Vec2d c = s[std::size_t(i) % s.size()].p;
            const Vec2d q = i % 3 == 0 ? c : Vec2d{c.x + 0.5 * u(rng), c.y + 0.5 * u(rng)};
            const auto r = test::interpolate(o, s, q);
            ASSERT_TRUE(std::isfinite(r.value)) << method_name(m) << " k=" << k;
          }
        }
      }
    }
  }
}

TEST(InterpolationWeights, RejectsBadArguments) {
  std::vector<Vec2d> nb(21);
  std::vector<double> w(21);
  EXPECT_THROW(interpolation_weights(opts(InterpMethod::msm, 21), nb, {0, 0}, w), std::invalid_argument);
  std::vector<Vec2d> one = {{0, 0}};
  std::vector<double> w1(1);
  EXPECT_THROW(interpolation_weights(opts(InterpMethod::msm, 1), one, {NAN, 0}, w1), std::invalid_argument);
}

}  // namespace
}  // namespace foveart::foveation
