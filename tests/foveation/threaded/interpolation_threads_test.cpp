// The interpolation on the executor (table build, per-frame gather, TAA)
// gives the same bits for any thread count and is data-race free (this suite
// runs under ThreadSanitizer in CI).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>

#include "foveation/executor.hpp"
#include "foveation/gather.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/interpolation_table.hpp"
#include "foveation/point_set.hpp"
#include "foveation/temporal_blend.hpp"

namespace fv = foveart::foveation;

TEST(ThreadedInterpolation, TableGatherAndTaaAgreeAcrossThreadCounts) {
  auto d = fv::DisplayModel::from_thesis(96, 80, 0.85);
  d.scale = 3.0;
  const auto ps = fv::generate_point_set(d, 5);
  fv::Executor one_thread(1), two_threads(2), three_threads(3);
  const auto nt = fv::NeighborTable::build(ps, 10, two_threads);
  fv::InterpOptions o;
  o.method = fv::InterpMethod::rbf;
  o.k = 10;
  const auto t1 = fv::build_interpolation_table(ps, nt, o, one_thread, fv::WeightPrecision::f16);
  // Two builds at once sharing one executor's workers, and one progress callback on the caller.
  fv::InterpolationTable a, b;
  const auto caller = std::this_thread::get_id();
  std::thread ta([&] { a = fv::build_interpolation_table(ps, nt, o, three_threads, fv::WeightPrecision::f16); });
  double last = -1.0;
  b = fv::build_interpolation_table(ps, nt, o, three_threads, fv::WeightPrecision::f16, [&](double f) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    EXPECT_GE(f, last);
    last = f;
  });
  ta.join();
  EXPECT_EQ(last, 1.0);
  EXPECT_EQ(a.weights_f16, t1.weights_f16);
  EXPECT_EQ(b.weights_f16, t1.weights_f16);
  EXPECT_EQ(a.layout.slot, t1.layout.slot);  // the gather layout is built on the same workers
  EXPECT_EQ(b.layout.palette, t1.layout.palette);

  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> rgb(ps.size() * 3);
  for (float& v : rgb) v = u(rng);
  rgb[7] = NAN;  // one invalid point: the slow path runs on some worker too
  const auto colors = fv::point_colors_from_all(rgb);
  const auto map = fv::map_gaze(96, 80, {30.0f, 50.0f});
  fv::ImageRgb one, two;
  fv::gather(nt, t1, colors, map, one, one_thread);
  fv::gather(nt, t1, colors, map, two, two_threads);
  EXPECT_EQ(one.rgb, two.rgb);
  fv::gather(nt, t1, colors, map, two, three_threads);  // bands of whole tile rows: same bits for any split
  EXPECT_EQ(one.rgb, two.rgb);

  fv::TemporalAccumulator taa1, taa2;
  for (int f = 0; f < 3; ++f) {
    for (float& v : one.rgb) v = 0.9f * v + 0.1f * u(rng);
    EXPECT_EQ(taa1.accumulate(one, map.gaze_px, one_thread).rgb, taa2.accumulate(one, map.gaze_px, two_threads).rgb);
  }
}
