// Cache round trip, and every kind of bad cache rejected (never served).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <numeric>
#include <unistd.h>
#include <glm/geometric.hpp>

#include <fstream>

#include <xxhash.h>

#include "foveation/point_set_cache.hpp"
#include "test_executor.hpp"

namespace fv = foveart::foveation;
namespace fs = std::filesystem;

namespace {

class CacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("foveart_cache_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    key_.display = fv::DisplayModel::from_thesis(100, 80, 0.85);
    key_.display.scale = 3.0;
    key_.seed = 3;
    key_.k = 6;
    points_ = fv::generate_point_set(key_.display, key_.seed);
    table_ = fv::NeighborTable::build(points_, key_.k, fv::test::executor());
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<char> read(const fs::path& f) {
    std::ifstream in(f, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void write(const fs::path& f, const std::vector<char>& bytes) {
    std::ofstream out(f, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  }
  // The file is rejected with a message containing `why`.
  void expect_rejected(const fs::path& f, const std::string& why) {
    std::string err;
    EXPECT_FALSE(fv::load_point_set(f, key_, &err).has_value());
    EXPECT_NE(err.find(why), std::string::npos) << err;
    EXPECT_NE(err.find(f.string()), std::string::npos) << "message names the file: " << err;
  }

  // The cache format (foveation/src/point_set_cache.cpp): a 136-byte header
  // with payload_bytes at 88, payload_xxh3 at 96 and header_xxh3 (over bytes
  // 0..127) at 128, then the payload. Recomputes the checksums so that a
  // crafted payload passes every check but the one under test.
  static constexpr std::size_t kHeaderBytes = 136;
  static void reseal(std::vector<char>* bytes) {
    const std::uint64_t payload_bytes = bytes->size() - kHeaderBytes;
    const std::uint64_t payload_xxh3 = XXH3_64bits(bytes->data() + kHeaderBytes, payload_bytes);
    std::memcpy(bytes->data() + 88, &payload_bytes, 8);
    std::memcpy(bytes->data() + 96, &payload_xxh3, 8);
    const std::uint64_t header_xxh3 = XXH3_64bits(bytes->data(), 128);
    std::memcpy(bytes->data() + 128, &header_xxh3, 8);
  }

  fs::path dir_;
  fv::PointSetKey key_;
  fv::PointSet points_;
  fv::NeighborTable table_;
};

}  // namespace

TEST_F(CacheTest, RoundTrip) {
  const auto pf = fv::point_set_cache_path(dir_, key_);
  const auto tf = fv::neighbor_table_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_point_set(pf, key_, points_), "");
  ASSERT_EQ(fv::save_neighbor_table(tf, key_, table_), "");
  std::string err;
  const auto ps = fv::load_point_set(pf, key_, &err);
  ASSERT_TRUE(ps.has_value()) << err;
  ASSERT_EQ(ps->size(), points_.size());
  EXPECT_EQ(0, std::memcmp(ps->position_px.data(), points_.position_px.data(), points_.size() * sizeof(glm::vec2)));
  EXPECT_EQ(ps->radius_px, points_.radius_px);
  EXPECT_EQ(ps->footprint, points_.footprint);
  EXPECT_EQ(ps->visible_margin_px, points_.visible_margin_px);
  EXPECT_EQ(ps->exact_fovea_radius_px, points_.exact_fovea_radius_px);
  EXPECT_GT(ps->exact_fovea_radius_px, 0.0f);
  EXPECT_GT(std::count(ps->footprint.begin(), ps->footprint.end(), fv::PointFootprint::kPixel), 100);
  const auto t = fv::load_neighbor_table(tf, key_, &err);
  ASSERT_TRUE(t.has_value()) << err;
  EXPECT_EQ(t->packed(), table_.packed());
  EXPECT_EQ(t->k(), 6);
  // The loaded table views a mapping of the file: it (and its copies) stay
  // valid after the file is replaced or removed.
  const fv::NeighborTable copy = *t;
  ASSERT_EQ(fv::save_neighbor_table(tf, key_, fv::NeighborTable::build(points_, 5, fv::test::executor())), "");
  fs::remove(tf);
  EXPECT_EQ(t->packed(), table_.packed());
  EXPECT_EQ(copy.packed(), table_.packed());
  EXPECT_EQ(copy.neighbor(copy.pixel_count() - 1, 5), table_.neighbor(table_.pixel_count() - 1, 5));
}

TEST_F(CacheTest, TruncatedCorruptForeignAndOtherVersionAreRejected) {
  const auto pf = fv::point_set_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_point_set(pf, key_, points_), "");
  const auto good = read(pf);

  expect_rejected(dir_ / "missing.fovc", "not found");

  auto bytes = good;
  bytes.resize(bytes.size() - 5);
  write(pf, bytes);
  expect_rejected(pf, "truncated");

  bytes = good;
  bytes.resize(40);
  write(pf, bytes);
  expect_rejected(pf, "truncated header");

  bytes = good;
  bytes[bytes.size() - 3] ^= 0x10;  // one bit in the footprints
  write(pf, bytes);
  expect_rejected(pf, "payload checksum");

  bytes = good;
  bytes[20] ^= 0x01;  // a parameter in the header
  write(pf, bytes);
  expect_rejected(pf, "header checksum");

  bytes = good;
  bytes[8] = 99;  // version field
  write(pf, bytes);
  expect_rejected(pf, "format version 99");

  bytes = good;
  bytes[0] = 'X';
  write(pf, bytes);
  expect_rejected(pf, "not a FoveaRT cache");

  write(pf, std::vector<char>(500, '\x42'));
  expect_rejected(pf, "not a FoveaRT cache");

  bytes = good;
  bytes.push_back('z');
  write(pf, bytes);
  expect_rejected(pf, "padded");

  // Other parameters: a valid file for another seed, scale or display.
  write(pf, good);
  for (auto mutate : std::vector<std::function<void(fv::PointSetKey&)>>{
           [](fv::PointSetKey& k) { k.seed = 4; },
           [](fv::PointSetKey& k) { k.display.scale = 1.5; },
           [](fv::PointSetKey& k) { k.display.view_distance_px += 1e-9; },
           [](fv::PointSetKey& k) { k.display.disc_rule = fv::DiscRule::kNonOverlapping; },
           [](fv::PointSetKey& k) { k.display.fovea_pattern = fv::FoveaPattern::kThesisPoisson; }}) {
    fv::PointSetKey other = key_;
    mutate(other);
    std::string err;
    EXPECT_FALSE(fv::load_point_set(pf, other, &err).has_value());
    EXPECT_NE(err.find("other parameters"), std::string::npos) << err;
  }

  // A neighbour table file is not a point set (and the other way round).
  const auto tf = fv::neighbor_table_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_neighbor_table(tf, key_, table_), "");
  expect_rejected(tf, "another kind");
  std::string err;
  EXPECT_FALSE(fv::load_neighbor_table(pf, key_, &err).has_value());
  fv::PointSetKey k7 = key_;
  k7.k = 7;
  EXPECT_FALSE(fv::load_neighbor_table(tf, k7, &err).has_value());
}

// A checksummed file that calls a point off a pixel centre a pixel-grid point
// (or has a footprint that does not exist) is rejected: its rays would
// sample the wrong pixel.
TEST_F(CacheTest, PixelFootprintOffAPixelCentreIsRejected) {
  const auto pf = fv::point_set_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_point_set(pf, key_, points_), "");
  const auto good = read(pf);
  const std::size_t footprints = good.size() - points_.size();
  std::size_t disc = 0;
  while (points_.on_pixel_grid(disc)) ++disc;
  for (char bad : {char(fv::PointFootprint::kPixel), char(7)}) {
    auto bytes = good;
    bytes[footprints + disc] = bad;
    reseal(&bytes);
    write(pf, bytes);
    expect_rejected(pf, "point " + std::to_string(disc) + " has footprint " + std::to_string(int(bad)));
  }
}

// A checksummed point set whose count is 2^62 more than its payload holds
// (13 bytes a point): rejected before any allocation, naming the file and
// the field, and rebuilt by load_or_build_tables.
TEST_F(CacheTest, PointCountThatWrapsThePayloadSizeIsRejected) {
  const auto pf = fv::point_set_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_point_set(pf, key_, points_), "");
  auto bytes = read(pf);
  auto resealed = bytes;
  reseal(&resealed);
  ASSERT_EQ(resealed, bytes) << "the test's view of the format is out of date";
  // Payload: canvas width and height (2 x u32), then the u64 point count.
  constexpr std::size_t kCountOffset = kHeaderBytes + 8;
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data() + kCountOffset, sizeof n);
  ASSERT_EQ(n, points_.size());
  n += std::uint64_t{1} << 62;  // resize(n) would throw or exhaust memory
  std::memcpy(bytes.data() + kCountOffset, &n, sizeof n);
  reseal(&bytes);
  write(pf, bytes);

  std::string err;
  std::optional<fv::PointSet> loaded;
  EXPECT_NO_THROW(loaded = fv::load_point_set(pf, key_, &err));
  EXPECT_FALSE(loaded.has_value());
  EXPECT_NE(err.find(pf.string()), std::string::npos) << err;
  EXPECT_NE(err.find("point count " + std::to_string(n)), std::string::npos) << err;

  std::vector<std::string> log;
  fv::FoveationTables tables;
  EXPECT_NO_THROW(tables = fv::load_or_build_tables(dir_, key_, fv::test::executor(), {},
                                                    [&](const std::string& s) { log.push_back(s); }));
  EXPECT_FALSE(tables.points_from_cache);
  EXPECT_EQ(tables.points.size(), points_.size());
  ASSERT_FALSE(log.empty());
  EXPECT_NE(log[0].find(pf.string()), std::string::npos) << log[0];
  EXPECT_NE(log[0].find("point count"), std::string::npos) << log[0];
  EXPECT_NE(log[0].find("rebuilding"), std::string::npos) << log[0];
  EXPECT_TRUE(fv::load_point_set(pf, key_, &err).has_value()) << "the cache is repaired: " << err;
}

// A checksummed neighbour table whose width x height x k x 3 wraps to its
// one-byte payload (2^30 x 2^30 x 16 x 3 = 3 x 2^64) is rejected, naming the
// file, instead of served as a table of 2^60 pixels over one byte.
TEST_F(CacheTest, TableDimensionsThatWrapThePayloadSizeAreRejected) {
  const auto tf = fv::neighbor_table_cache_path(dir_, key_);
  ASSERT_EQ(fv::save_neighbor_table(tf, key_, table_), "");
  auto bytes = read(tf);
  auto resealed = bytes;
  reseal(&resealed);
  ASSERT_EQ(resealed, bytes) << "the test's view of the format is out of date";
  // Payload: packed entries plus one byte of padding, then width, height, k (3 x u32).
  const std::uint32_t dims[3] = {1u << 30, 1u << 30, 16};
  bytes.resize(kHeaderBytes + 1 + sizeof dims);
  bytes[kHeaderBytes] = 0;
  std::memcpy(bytes.data() + kHeaderBytes + 1, dims, sizeof dims);
  reseal(&bytes);
  write(tf, bytes);

  std::string err;
  std::optional<fv::NeighborTable> loaded;
  EXPECT_NO_THROW(loaded = fv::load_neighbor_table(tf, key_, &err));
  EXPECT_FALSE(loaded.has_value()) << "served a table of " << loaded->pixel_count() << " pixels";
  EXPECT_NE(err.find(tf.string()), std::string::npos) << err;
  EXPECT_NE(err.find("table dimensions 1073741824x1073741824, k 16"), std::string::npos) << err;
}

TEST_F(CacheTest, LoadOrBuildRebuildsABadCacheAndSaysSo) {
  std::vector<std::string> log;
  auto first = fv::load_or_build_tables(dir_, key_, fv::test::executor(), {}, [&](const std::string& s) { log.push_back(s); });
  EXPECT_FALSE(first.points_from_cache);
  EXPECT_FALSE(first.neighbors_from_cache);
  auto second = fv::load_or_build_tables(dir_, key_, fv::test::executor());
  EXPECT_TRUE(second.points_from_cache);
  EXPECT_TRUE(second.neighbors_from_cache);
  EXPECT_EQ(second.neighbors.packed(), first.neighbors.packed());

  // Corrupt the table: reported, rebuilt, identical result, cache repaired.
  const auto tf = fv::neighbor_table_cache_path(dir_, key_);
  auto bytes = read(tf);
  bytes[bytes.size() / 2] ^= 0x7F;
  write(tf, bytes);
  log.clear();
  auto third = fv::load_or_build_tables(dir_, key_, fv::test::executor(), {}, [&](const std::string& s) { log.push_back(s); });
  EXPECT_FALSE(third.neighbors_from_cache);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("checksum"), std::string::npos) << log[0];
  EXPECT_EQ(third.neighbors.packed(), first.neighbors.packed());
  EXPECT_TRUE(fv::load_or_build_tables(dir_, key_, fv::test::executor()).neighbors_from_cache);
}

// A checksummed table whose indices overrun the cached point set (> 65,536
// points, so the index check's 8-entries-at-a-time path runs) is rebuilt.
TEST(CacheIndexCheck, TableIndexingBeyondThePointSetIsRebuilt) {
  const fs::path dir = fs::temp_directory_path() / ("foveart_cache_index_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fv::PointSetKey key;
  key.display = fv::DisplayModel::from_thesis(96, 96, 0.3);
  key.display.fovea_pattern = fv::FoveaPattern::kThesisPoisson;  // ~2 points per pixel: > 65,536
  key.seed = 2;
  key.k = 3;
  const auto first = fv::load_or_build_tables(dir, key, fv::test::executor());
  ASSERT_GT(first.points.size(), 70000u);
  fv::PointSet fewer = first.points;
  fewer.position_px.resize(fewer.size() - 500);
  fewer.radius_px.resize(fewer.position_px.size());
  ASSERT_EQ(fv::save_point_set(fv::point_set_cache_path(dir, key), key, fewer), "");
  std::vector<std::string> log;
  const auto second = fv::load_or_build_tables(dir, key, fv::test::executor(), {}, [&](const std::string& s) { log.push_back(s); });
  EXPECT_TRUE(second.points_from_cache);
  EXPECT_FALSE(second.neighbors_from_cache);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_NE(log[0].find("does not match the point set"), std::string::npos) << log[0];
  // The rebuilt table fits the smaller set and is served from then on.
  const auto third = fv::load_or_build_tables(dir, key, fv::test::executor());
  EXPECT_TRUE(third.neighbors_from_cache);
  EXPECT_EQ(third.neighbors.packed(), second.neighbors.packed());
  std::uint32_t max_index = 0;
  for (std::size_t p = 0; p < third.neighbors.pixel_count(); ++p) {
    for (int j = 0; j < key.k; ++j) max_index = std::max(max_index, third.neighbors.neighbor(p, j));
  }
  EXPECT_LT(max_index, fewer.size());
  EXPECT_GE(max_index, 65536u);
  fs::remove_all(dir);
}
