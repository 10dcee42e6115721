// Versioned, checksummed cache files for the point set and neighbour table.
//
// File = Header (fixed 128 bytes, little-endian, host layout checked below) +
// payload. The header records every parameter the data depends on; the payload
// and the header each carry an XXH3-64 checksum.
#include "foveation/point_set_cache.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <sstream>

#include <xxhash.h>

#include "cache_file.hpp"
#include "foveation/elapsed.hpp"

namespace foveart::foveation {
namespace {

constexpr char kMagic[8] = {'F', 'O', 'V', 'E', 'A', 'R', 'T', 'C'};
enum class Kind : std::uint32_t { kPointSet = 1, kNeighborTable = 2 };

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint32_t kind;
  // Key: every parameter the data depends on.
  std::int32_t width_px;
  std::int32_t height_px;
  double view_distance_px;
  double scale;
  double ct0;
  double alpha;
  double e2_deg;
  std::uint64_t seed;
  std::int32_t k;
  std::int32_t disc_rule;
  std::int32_t fovea_pattern;
  std::int32_t reserved_key;  // 0
  // Payload description.
  std::uint64_t payload_bytes;
  std::uint64_t payload_xxh3;
  std::uint8_t reserved[24];
  std::uint64_t header_xxh3;  // over every byte above
};
static_assert(sizeof(Header) == 136, "cache header layout changed: bump kCacheFormatVersion");

Header make_header(Kind kind, const PointSetKey& key) {
  Header h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = kCacheFormatVersion;
  h.kind = std::uint32_t(kind);
  h.width_px = key.display.width_px;
  h.height_px = key.display.height_px;
  h.view_distance_px = key.display.view_distance_px;
  h.scale = key.display.scale;
  h.ct0 = key.display.csf.ct0;
  h.alpha = key.display.csf.alpha;
  h.e2_deg = key.display.csf.e2_deg;
  h.seed = key.seed;
  h.k = (kind == Kind::kPointSet) ? 0 : key.k;
  h.disc_rule = int(key.display.disc_rule);
  h.fovea_pattern = int(key.display.fovea_pattern);
  return h;
}

std::uint64_t header_checksum(const Header& h) { return XXH3_64bits(&h, offsetof(Header, header_xxh3)); }

std::string key_hex(Kind kind, const PointSetKey& key) {
  const Header h = make_header(kind, key);
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx",
                static_cast<unsigned long long>(XXH3_64bits(&h, offsetof(Header, payload_bytes))));
  return buf;
}

// Header + payload pieces, written from their owners' memory (the 442 MB
// table is never copied).
std::string save_file(const std::filesystem::path& file, Header h, std::initializer_list<detail::ByteSpan> payload) {
  h.payload_bytes = 0;
  for (const detail::ByteSpan& b : payload) h.payload_bytes += b.size;
  h.payload_xxh3 = detail::xxh3_of(std::span(payload.begin(), payload.size()));
  h.header_xxh3 = header_checksum(h);
  std::vector<detail::ByteSpan> pieces{{&h, sizeof h}};
  pieces.insert(pieces.end(), payload.begin(), payload.end());
  return write_file_atomically(file, pieces);
}

// Maps and checks the whole file; the payload view on success, nullopt with *error on any mismatch.
std::optional<detail::MappedFile> load_file(const std::filesystem::path& file, Kind kind, const PointSetKey& key,
                                            std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "cache " + file.string() + ": " + why;
    return std::nullopt;
  };
  std::string why;
  auto m = detail::map_file(file, &why);
  if (!m) return fail(why);
  Header h{};
  if (m->size < sizeof h) return fail("truncated header");
  std::memcpy(&h, m->bytes, sizeof h);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return fail("not a FoveaRT cache file");
  if (h.version != kCacheFormatVersion) {
    return fail("format version " + std::to_string(h.version) + ", expected " +
                std::to_string(kCacheFormatVersion));
  }
  if (h.header_xxh3 != header_checksum(h)) return fail("header checksum mismatch (corrupt)");
  if (h.kind != std::uint32_t(kind)) return fail("holds another kind of data");
  const Header want = make_header(kind, key);
  if (std::memcmp(&h.width_px, &want.width_px, offsetof(Header, payload_bytes) - offsetof(Header, width_px)) != 0) {
    std::ostringstream msg;
    msg << "built for other parameters (" << h.width_px << "x" << h.height_px << ", view distance "
        << h.view_distance_px << " px, scale " << h.scale << ", seed " << h.seed << ", k " << h.k << ", pattern "
        << h.fovea_pattern << ")";
    return fail(msg.str());
  }
  const std::uint64_t remaining = m->size - sizeof h;
  if (remaining != h.payload_bytes) {
    return fail("payload is " + std::to_string(remaining) + " bytes, header says " +
                std::to_string(h.payload_bytes) + " (truncated or padded)");
  }
  detail::MappedFile payload{m->owner, m->bytes + sizeof h, std::size_t(remaining)};
  if (XXH3_64bits(payload.bytes, payload.size) != h.payload_xxh3) return fail("payload checksum mismatch (corrupt)");
  return payload;
}

// True when `count` elements of `element_bytes` each fill exactly `bytes`:
// checked by division, so a count from a crafted header cannot wrap the product.
bool count_fills_exactly(std::uint64_t count, std::uint64_t element_bytes, std::uint64_t bytes) {
  return element_bytes != 0 && bytes % element_bytes == 0 && count == bytes / element_bytes;
}

}  // namespace

std::filesystem::path point_set_cache_path(const std::filesystem::path& dir, const PointSetKey& key) {
  return dir / ("points_" + key_hex(Kind::kPointSet, key) + ".fovc");
}

std::filesystem::path neighbor_table_cache_path(const std::filesystem::path& dir, const PointSetKey& key) {
  return dir / ("neighbors_k" + std::to_string(key.k) + "_" + key_hex(Kind::kNeighborTable, key) + ".fovc");
}

std::string save_point_set(const std::filesystem::path& file, const PointSetKey& key, const PointSet& points) {
  const std::uint32_t dims[2] = {std::uint32_t(points.canvas_width_px), std::uint32_t(points.canvas_height_px)};
  const std::uint64_t n = points.size();
  // Footprints always stored (a disc each when the set has none), so the payload size follows from n.
  std::vector<PointFootprint> discs;
  if (points.footprint.size() != points.size()) discs.assign(points.size(), PointFootprint::kDisc);
  const std::vector<PointFootprint>& footprint = discs.empty() ? points.footprint : discs;
  return save_file(file, make_header(Kind::kPointSet, key),
                   {detail::bytes_of(dims, 2), detail::bytes_of(&n, 1), detail::bytes_of(points.position_px.data(), points.size()),
                    detail::bytes_of(points.radius_px.data(), points.size()),
                    detail::bytes_of(footprint.data(), footprint.size())});
}

std::optional<PointSet> load_point_set(const std::filesystem::path& file, const PointSetKey& key,
                                       std::string* error) {
  auto payload = load_file(file, Kind::kPointSet, key, error);
  if (!payload) return std::nullopt;
  auto fail = [&](const std::string& why) {
    if (error) *error = "cache " + file.string() + ": " + why;
    return std::nullopt;
  };
  std::uint32_t dims[2];
  std::uint64_t n = 0;
  if (payload->size < sizeof dims + sizeof n) return fail("payload too short");
  std::memcpy(dims, payload->bytes, sizeof dims);
  std::memcpy(&n, payload->bytes + sizeof dims, sizeof n);
  // Before any allocation: the count comes from the file.
  const std::uint64_t point_bytes = payload->size - sizeof dims - sizeof n;
  if (!count_fills_exactly(n, sizeof(glm::vec2) + sizeof(float) + sizeof(PointFootprint), point_bytes)) {
    return fail("point count " + std::to_string(n) + " does not match the payload size (" +
                std::to_string(point_bytes) + " bytes of points)");
  }
  if (int(dims[0]) != key.display.canvas_width_px() || int(dims[1]) != key.display.canvas_height_px()) {
    return fail("canvas size does not match the display");
  }
  PointSet ps;
  ps.canvas_width_px = int(dims[0]);
  ps.canvas_height_px = int(dims[1]);
  ps.position_px.resize(n);
  ps.radius_px.resize(n);
  const std::uint8_t* p = payload->bytes + sizeof dims + sizeof n;
  std::memcpy(ps.position_px.data(), p, n * sizeof(glm::vec2));
  std::memcpy(ps.radius_px.data(), p + n * sizeof(glm::vec2), n * sizeof(float));
  const bool pixel_grid = key.display.fovea_pattern == FoveaPattern::kPixelGrid;
  ps.visible_margin_px = pixel_grid ? 0.0f : kVisibleMarginPx;
  ps.exact_fovea_radius_px = float(key.display.exact_fovea_radius_px());
  ps.view_distance_px = float(key.display.view_distance_px);
  if (pixel_grid) {
    ps.footprint.resize(n);
    std::memcpy(ps.footprint.data(), p + n * (sizeof(glm::vec2) + sizeof(float)), n * sizeof(PointFootprint));
  }
  const std::uint8_t* footprint_bytes = p + n * (sizeof(glm::vec2) + sizeof(float));
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec2 q = ps.position_px[i];
    if (!(q.x >= 0.0f && q.y >= 0.0f && q.x < float(dims[0]) && q.y < float(dims[1])) ||
        !(ps.radius_px[i] > 0.0f)) {
      return fail("point " + std::to_string(i) + " is outside the canvas or has no radius");
    }
    const std::uint8_t f = footprint_bytes[i];
    const bool centred = q.x - std::floor(q.x) == 0.5f && q.y - std::floor(q.y) == 0.5f;
    if (f > std::uint8_t(PointFootprint::kPixel) || (f == std::uint8_t(PointFootprint::kPixel) && (!pixel_grid || !centred))) {
      return fail("point " + std::to_string(i) + " has footprint " + std::to_string(f) +
                  " (a pixel footprint needs the pixel-grid pattern and a pixel centre)");
    }
  }
  return ps;
}

std::string save_neighbor_table(const std::filesystem::path& file, const PointSetKey& key,
                                const NeighborTable& table) {
  // Packed entries first, dimensions last: loading then views the mapped
  // payload as the table without copying 442 MB.
  const std::uint32_t dims[3] = {std::uint32_t(table.width_px()), std::uint32_t(table.height_px()),
                                 std::uint32_t(table.k())};
  PointSetKey k = key;
  k.k = table.k();
  return save_file(file, make_header(Kind::kNeighborTable, k),
                   {detail::bytes_of(table.packed().data(), table.packed().size()), detail::bytes_of(dims, 3)});
}

std::optional<NeighborTable> load_neighbor_table(const std::filesystem::path& file, const PointSetKey& key,
                                                 std::string* error) {
  auto payload = load_file(file, Kind::kNeighborTable, key, error);
  if (!payload) return std::nullopt;
  auto fail = [&](const std::string& why) {
    if (error) *error = "cache " + file.string() + ": " + why;
    return std::nullopt;
  };
  std::uint32_t dims[3];
  if (payload->size < sizeof dims + 1) return fail("payload too short");
  std::memcpy(dims, payload->bytes + payload->size - sizeof dims, sizeof dims);
  // The table views the mapped file (no copy); the dims after it are its readable tail.
  // from_packed checks the dimensions against the size without a product a
  // crafted header could wrap, before anything reads the entries.
  std::optional<NeighborTable> table;
  try {
    table = NeighborTable::from_packed(int(dims[0]), int(dims[1]), int(dims[2]), std::move(payload->owner),
                                       payload->bytes, payload->size - sizeof dims);
  } catch (const std::invalid_argument& e) {
    return fail(e.what());
  }
  if (table->k() != key.k) return fail("table k " + std::to_string(table->k()) + " differs from its header's");
  return table;
}

namespace {

// True when every 24-bit entry addresses one of `count` points. Tests the high
// bytes of 8 entries (24 bytes, 3 words) at once; only blocks where one could be
// too large are decoded entry by entry.
bool all_indices_below(const NeighborTable& t, std::size_t count) {
  const std::uint8_t* p = t.packed().data();
  const std::size_t entries = t.pixel_count() * std::size_t(t.k());
  auto decode_ok = [&](std::size_t e) {
    const std::uint32_t v = std::uint32_t(p[3 * e]) | (std::uint32_t(p[3 * e + 1]) << 8) |
                            (std::uint32_t(p[3 * e + 2]) << 16);
    return v < count;
  };
  std::size_t e = 0;
  const std::uint64_t high_ok = count >> 16;  // a high byte below this is always valid
  if (high_ok >= 1 && high_ok <= 128) {
    // Bytewise "any byte > n" (Anderson, Bit Twiddling Hacks, hasmore), n <= 127;
    // false positives are harmless (exact check), there are no false negatives.
    constexpr std::uint64_t kOnes = ~std::uint64_t{0} / 255;
    const std::uint64_t add = kOnes * (127 - (high_ok - 1));
    auto any_above = [&](std::uint64_t x) { return ((x + add) | x) & (kOnes * 128); };
    constexpr std::uint64_t kMask[3] = {0x0000FF0000FF0000ull, 0x00FF0000FF0000FFull, 0xFF0000FF0000FF00ull};
    for (; e + 8 <= entries; e += 8) {
      std::uint64_t w[3];
      std::memcpy(w, p + 3 * e, sizeof w);
      if (any_above(w[0] & kMask[0]) | any_above(w[1] & kMask[1]) | any_above(w[2] & kMask[2])) {
        for (std::size_t i = e; i < e + 8; ++i) {
          if (!decode_ok(i)) return false;
        }
      }
    }
  }
  for (; e < entries; ++e) {
    if (!decode_ok(e)) return false;
  }
  return true;
}

}  // namespace

FoveationTables load_or_build_tables(const std::optional<std::filesystem::path>& cache_dir,
                                     const PointSetKey& key, Executor& executor, const ProgressFn& progress,
                                     const LogFn& log) {
  FoveationTables out;
  auto say = [&](const std::string& s) { if (log) log(s); };
  // The point set is ~10% of the work, the table ~90%.
  auto sub = [&](double lo, double hi) -> ProgressFn {
    if (!progress) return {};
    return [=, &progress](double f) { progress(lo + (hi - lo) * f); };
  };

  auto t0 = std::chrono::steady_clock::now();
  std::string err;
  if (cache_dir) {
    if (auto ps = load_point_set(point_set_cache_path(*cache_dir, key), key, &err)) {
      out.points = std::move(*ps);
      out.points_from_cache = true;
    } else if (std::filesystem::exists(point_set_cache_path(*cache_dir, key))) {
      say(err + "; rebuilding");
    }
  }
  if (!out.points_from_cache) {
    out.points = generate_point_set(key.display, key.seed, sub(0.0, 0.1));
    if (cache_dir) {
      if (auto e = save_point_set(point_set_cache_path(*cache_dir, key), key, out.points); !e.empty()) say(e);
    }
  }
  out.generation_ms = ms_since(t0);

  t0 = std::chrono::steady_clock::now();
  bool have_table = false;
  if (cache_dir) {
    if (auto t = load_neighbor_table(neighbor_table_cache_path(*cache_dir, key), key, &err)) {
      // Only trust a table whose indices all address this point set.
      bool valid = out.points_from_cache &&  // never pair a table with a rebuilt point set
                   t->width_px() == out.points.canvas_width_px && t->height_px() == out.points.canvas_height_px &&
                   all_indices_below(*t, out.points.size());
      if (valid) {
        out.neighbors = std::move(*t);
        have_table = true;
        out.neighbors_from_cache = true;
      } else {
        say("cache " + neighbor_table_cache_path(*cache_dir, key).string() +
            ": does not match the point set; rebuilding");
      }
    } else if (std::filesystem::exists(neighbor_table_cache_path(*cache_dir, key))) {
      say(err + "; rebuilding");
    }
  }
  if (!have_table) {
    out.neighbors = NeighborTable::build(out.points, key.k, executor, sub(0.1, 1.0));
    if (cache_dir) {
      if (auto e = save_neighbor_table(neighbor_table_cache_path(*cache_dir, key), key, out.neighbors); !e.empty()) {
        say(e);
      }
    }
  }
  out.table_ms = ms_since(t0);
  if (progress) progress(1.0);
  return out;
}

}  // namespace foveart::foveation
