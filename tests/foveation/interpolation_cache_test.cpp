// The interpolation table cache: round trip, and every kind of bad file is
// rejected with a message saying which, then rebuilt.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/interpolation_cache.hpp"
#include "interpolation_fixture.hpp"
#include "test_executor.hpp"

namespace foveart::foveation {
namespace {

namespace fs = std::filesystem;

struct InterpolationCacheTest : ::testing::Test {
  void SetUp() override {
    dir = fs::temp_directory_path() / ("foveart_interp_cache_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir);
    key.display.name = "test";
    key.display.width_px = test::kScreenW;
    key.display.height_px = test::kScreenH;
    key.display.view_distance_px = 100.0;
    key.seed = 3;
    opts.method = InterpMethod::rbf;
    opts.k = 10;
  }
  void TearDown() override { fs::remove_all(dir); }

  CachedTable load_or_build(std::vector<std::string>* logs = nullptr) {
    return load_or_build_interpolation_table(dir, key, points, nt, opts, test::executor(), WeightPrecision::f16, {},
                                             [&](const std::string& m) { if (logs) logs->push_back(m); });
  }
  fs::path only_file() const {
    for (const auto& e : fs::directory_iterator(dir)) return e.path();
    return {};
  }

  fs::path dir;
  PointSetKey key;
  PointSet points = test::foveated_points(2);
  NeighborTable nt = NeighborTable::build(points, 10, test::executor());
  InterpOptions opts;
};

TEST_F(InterpolationCacheTest, RoundTripServesIdenticalWeights) {
  const auto built = load_or_build();
  EXPECT_FALSE(built.from_cache);
  const auto loaded = load_or_build();
  EXPECT_TRUE(loaded.from_cache);
  EXPECT_EQ(loaded.table.weights_f16, built.table.weights_f16);
  EXPECT_EQ(loaded.table.precision, WeightPrecision::f16);
  EXPECT_EQ(loaded.table.options.method, InterpMethod::rbf);
  EXPECT_EQ(loaded.table.stats.factorizations, built.table.stats.factorizations);
}

TEST_F(InterpolationCacheTest, TruncatedFileIsRejectedAndRebuilt) {
  load_or_build();
  const auto file = only_file();
  fs::resize_file(file, fs::file_size(file) - 7);
  std::vector<std::string> logs;
  const auto again = load_or_build(&logs);
  EXPECT_FALSE(again.from_cache);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_NE(logs[0].find("truncated"), std::string::npos) << logs[0];
  EXPECT_TRUE(load_or_build().from_cache);  // the rebuild was stored
}

TEST_F(InterpolationCacheTest, CorruptPayloadIsRejected) {
  load_or_build();
  const auto file = only_file();
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-3, std::ios::end);
    f.put('\x5a');
  }
  std::vector<std::string> logs;
  EXPECT_FALSE(load_or_build(&logs).from_cache);
  ASSERT_EQ(logs.size(), 1u);
  EXPECT_NE(logs[0].find("checksum"), std::string::npos) << logs[0];
}

TEST_F(InterpolationCacheTest, OtherVersionAndOtherParametersAreRejected) {
  load_or_build();
  const auto file = only_file();
  const auto params = interpolation_cache_params(key, points, opts, WeightPrecision::f16);
  std::string error;
  EXPECT_TRUE(load_interpolation_table(file, params, &error).has_value()) << error;
  // Another shape: other parameters (same file forced).
  auto other = opts;
  other.shape = 0.7;
  EXPECT_FALSE(load_interpolation_table(file, interpolation_cache_params(key, points, other, WeightPrecision::f16), &error));
  EXPECT_NE(error.find("other parameters"), std::string::npos) << error;
  // Moved points: other parameters, too (the point set checksum is in the key).
  auto moved = points;
  moved.position_px[5].x += 0.25f;
  EXPECT_FALSE(load_interpolation_table(file, interpolation_cache_params(key, moved, opts, WeightPrecision::f16), &error));
  EXPECT_NE(error.find("other parameters"), std::string::npos) << error;
  // Another format version.
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(8);
    const std::uint32_t v = kInterpCacheFormatVersion + 1;
    f.write(reinterpret_cast<const char*>(&v), 4);
  }
  EXPECT_FALSE(load_interpolation_table(file, params, &error));
  EXPECT_NE(error.find("format version"), std::string::npos) << error;
  // Not a cache file at all.
  { std::ofstream(file, std::ios::trunc) << "hello"; }
  EXPECT_FALSE(load_interpolation_table(file, params, &error));
  EXPECT_NE(error.find("magic"), std::string::npos) << error;
  EXPECT_FALSE(load_interpolation_table(dir / "nope.bin", params, &error));
  EXPECT_NE(error.find("missing"), std::string::npos) << error;
}

// The FOVE canvas at k = 20, built by the loader every frame uses (layer and tools): the
// interpolation table it holds in memory fits the budget, as does the neighbour table
// beside it; the weights are half floats, and taps plus weights are only part of it
// (palettes and the tile index come on top).
TEST(InterpolationMemory, K20FoveCanvasFitsTheBudget) {
  PointSetKey key;
  key.display = *display_preset("fove");
  InterpOptions options;
  options.method = InterpMethod::msm;
  options.k = 20;
  const std::shared_ptr<const ViewTables> tables = load_view_tables(std::nullopt, key, options, test::executor());
  ASSERT_NE(tables, nullptr);
  const InterpolationTable& table = tables->interpolation;
  const std::size_t canvas_pixels = std::size_t(2 * key.display.width_px) * std::size_t(2 * key.display.height_px);
  EXPECT_EQ(table.precision, kDefaultWeightPrecision);
  EXPECT_EQ(table.options.k, 20);
  RecordProperty("table_bytes", std::to_string(table.bytes()));
  EXPECT_LT(table.bytes(), kTableBudgetBytes);
  EXPECT_GT(table.bytes(), table_bytes(canvas_pixels, 20, WeightPrecision::f16));
  EXPECT_LT(table.bytes() + tables->neighbors.bytes(), 2 * kTableBudgetBytes) << "both tables of one eye";
}

}  // namespace
}  // namespace foveart::foveation
