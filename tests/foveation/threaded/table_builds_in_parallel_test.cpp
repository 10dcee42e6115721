// Multithreaded table builds give the same result as ever, and are data-race
// free (this suite runs under ThreadSanitizer in CI).
#include <gtest/gtest.h>

#include <thread>

#include "foveation/executor.hpp"
#include "foveation/neighbor_table.hpp"
#include "foveation/point_set.hpp"

namespace fv = foveart::foveation;

TEST(ThreadedNeighborTable, WorkersAgreeWithEachOtherAndWithItself) {
  auto d = fv::DisplayModel::from_thesis(96, 80, 0.85);
  d.scale = 3.0;
  const auto ps = fv::generate_point_set(d, 5);
  fv::Executor one_thread(1), shared(3);
  const auto reference = fv::NeighborTable::build(ps, 8, one_thread);
  // Two builds at once share one executor's workers and the read-only set.
  fv::NeighborTable a, b;
  std::thread ta([&] { a = fv::NeighborTable::build(ps, 8, shared); });
  std::thread tb([&] { b = fv::NeighborTable::build(ps, 8, shared); });
  ta.join();
  tb.join();
  EXPECT_EQ(a.packed(), reference.packed());
  EXPECT_EQ(b.packed(), reference.packed());
  // The progress callback runs on the calling thread only and ends at 1.
  double last = -1.0;
  const auto caller = std::this_thread::get_id();
  fv::NeighborTable::build(ps, 4, shared, [&](double f) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    EXPECT_GE(f, last);
    last = f;
  });
  EXPECT_EQ(last, 1.0);
}
