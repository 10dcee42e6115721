#include "gpu/table_pack.hpp"

#include <algorithm>
#include <cstring>

namespace foveart::gpu {
namespace {

std::size_t words_of_bytes(std::size_t bytes) { return (bytes + 3) / 4; }

// Appends `bytes` bytes at `src` as whole words (zero padded) plus `pad_words`.
std::uint32_t append_bytes(std::vector<std::uint32_t>& words, const void* src, std::size_t bytes,
                           std::size_t pad_words = 0) {
  const auto offset = static_cast<std::uint32_t>(words.size());
  words.resize(words.size() + words_of_bytes(bytes) + pad_words, 0u);
  if (bytes > 0) std::memcpy(words.data() + offset, src, bytes);
  return offset;
}

// What one tile row of each table adds to a chunk.
struct RowSpan {
  std::size_t tiles = 0, blocks = 0, palette = 0, pixels = 0;
};

// The pack's description of the tables, without chunks.
TablePack pack_description(const foveation::ViewTables& tables) {
  const foveation::InterpolationTable& t = tables.interpolation;
  TablePack pack;
  pack.weighted = t.has_weights();
  pack.f16 = t.precision == foveation::WeightPrecision::f16;
  pack.rbf = t.is_rbf();
  pack.k = t.taps();
  pack.neighbor_k = tables.neighbors.k();
  pack.canvas_width_px = tables.neighbors.width_px();
  pack.canvas_height_px = tables.neighbors.height_px();
  return pack;
}

// The canvas as rows of 8x8 tiles, and what a run of them takes in a chunk.
struct TileRows {
  TileRows(const foveation::ViewTables& tables, const TablePack& description)
      : pack(description),
        l(tables.interpolation.layout),
        width(description.canvas_width_px),
        height(description.canvas_height_px),
        tiles_x((width + foveation::kGatherTilePx - 1) / foveation::kGatherTilePx),
        rows((height + foveation::kGatherTilePx - 1) / foveation::kGatherTilePx),
        weight_bytes(description.f16 ? 2 : 4) {}

  RowSpan row_span(int r) const {
    RowSpan s;
    s.tiles = std::size_t(tiles_x);
    s.pixels =
        std::size_t(std::min(foveation::kGatherTilePx, height - r * foveation::kGatherTilePx)) * std::size_t(width);
    if (pack.weighted) {
      const std::size_t t0 = std::size_t(r) * std::size_t(tiles_x), t1 = t0 + std::size_t(tiles_x);
      s.blocks = l.tile_first_block[t1] - l.tile_first_block[t0];
      s.palette = l.block_palette[l.tile_first_block[t1]] - l.block_palette[l.tile_first_block[t0]];
    }
    return s;
  }

  std::size_t span_bytes(const RowSpan& s) const {
    if (!pack.weighted) return 4 * (kHeaderWords + words_of_bytes(s.pixels * std::size_t(pack.neighbor_k) * 3) + 1);
    return 4 * (kHeaderWords + s.tiles + s.blocks + 1 + s.palette + words_of_bytes(s.pixels * std::size_t(pack.k)) +
                words_of_bytes(s.pixels * std::size_t(pack.k) * weight_bytes));
  }

  // The end of the longest run of rows from r0 that fits in max_bytes (r0 if none), and its span.
  int rows_that_fit(int r0, std::size_t max_bytes, RowSpan* total) const {
    int r1 = r0;
    while (r1 < rows) {
      const RowSpan s = row_span(r1);
      const RowSpan grown{total->tiles + s.tiles, total->blocks + s.blocks, total->palette + s.palette,
                          total->pixels + s.pixels};
      if (span_bytes(grown) > max_bytes) break;
      *total = grown;
      ++r1;
    }
    return r1;
  }

  const TablePack& pack;
  const foveation::GatherLayout& l;
  int width, height, tiles_x, rows;
  std::size_t weight_bytes;
};

// The chunk of tile rows [r0, r1): its header, then the weighted tables' sections or the neighbours.
TableChunk pack_chunk(const foveation::ViewTables& tables, const TablePack& pack, const TileRows& rows, int r0,
                         int r1, const RowSpan& total) {
  const foveation::InterpolationTable& t = tables.interpolation;
  const foveation::GatherLayout& l = t.layout;
  TableChunk chunk;
  chunk.first_row = std::uint32_t(r0);
  chunk.end_row = std::uint32_t(r1);
  auto& w = chunk.words;
  w.assign(kHeaderWords, 0u);
  w[kFirstRow] = chunk.first_row;
  w[kEndRow] = chunk.end_row;
  const std::size_t first_pixel = std::size_t(r0) * foveation::kGatherTilePx * std::size_t(rows.width);  // both orders
  w[kOrdinalBase] = std::uint32_t(first_pixel);
  w[kPixelBase] = std::uint32_t(first_pixel);
  if (!pack.weighted) {
    const std::size_t entry = std::size_t(pack.neighbor_k) * 3;
    w[kNeighbors] = append_bytes(w, tables.neighbors.packed().data() + first_pixel * entry, total.pixels * entry, 1);
    return chunk;
  }
  const std::size_t t0 = std::size_t(r0) * std::size_t(rows.tiles_x), t1 = std::size_t(r1) * std::size_t(rows.tiles_x);
  const std::uint32_t b0 = l.tile_first_block[t0], b1 = l.tile_first_block[t1];
  const std::uint32_t p0 = l.block_palette[b0], p1 = l.block_palette[b1];
  w[kBlockBase] = b0;
  w[kPaletteBase] = p0;
  w[kTileInfo] = std::uint32_t(w.size());
  for (std::size_t tile = t0; tile < t1; ++tile)
    w.push_back((l.tile_first_block[tile] - b0) | (std::uint32_t(l.tile_level[tile]) << 30));
  w[kBlockPalette] = std::uint32_t(w.size());
  for (std::uint32_t b = b0; b <= b1; ++b) w.push_back(l.block_palette[b] - p0);
  w[kPalette] = append_bytes(w, l.palette.data() + p0, std::size_t(p1 - p0) * 4);
  const std::size_t taps0 = first_pixel * std::size_t(pack.k), taps = total.pixels * std::size_t(pack.k);
  w[kSlots] = append_bytes(w, l.slot.data() + taps0, taps);
  w[kWeights] = pack.f16 ? append_bytes(w, t.weights_f16.data() + taps0, taps * 2)
                         : append_bytes(w, t.weights_f32.data() + taps0, taps * 4);
  return chunk;
}

}  // namespace

std::size_t TablePack::bytes() const {
  std::size_t n = 0;
  for (const auto& c : chunks) n += c.words.size() * 4;
  return n;
}

std::string tables_unsupported(const foveation::ViewTables& tables) {
  const auto& t = tables.interpolation;
  if (t.has_weights() && !t.normalized()) {
    return "plain RBF (no constant term) keeps a per-pixel gain the shaders do not apply";
  }
  if (t.has_weights() && tables.neighbors.k() != t.k()) {
    return "the neighbour table keeps more entries than the interpolation's taps";
  }
  return {};
}

bool pack_tables(const foveation::ViewTables& tables, std::size_t max_chunk_bytes, TablePack* out,
                     std::string* error) {
  if (std::string why = tables_unsupported(tables); !why.empty()) return *error = why, false;
  TablePack pack = pack_description(tables);
  const TileRows rows(tables, pack);
  for (int r0 = 0; r0 < rows.rows;) {
    RowSpan total;
    const int r1 = rows.rows_that_fit(r0, max_chunk_bytes, &total);
    if (r1 == r0) {
      return *error = "one row of 8x8 canvas tiles needs " + std::to_string(rows.span_bytes(rows.row_span(r0))) +
                      " bytes, more than a storage buffer's " + std::to_string(max_chunk_bytes),
             false;
    }
    if (pack.chunks.size() == kMaxTableChunks) {
      return *error = "the tables need more than " + std::to_string(kMaxTableChunks) + " buffers of " +
                      std::to_string(max_chunk_bytes) + " bytes",
             false;
    }
    pack.chunks.push_back(pack_chunk(tables, pack, rows, r0, r1, total));
    r0 = r1;
  }
  *out = std::move(pack);
  return true;
}

}  // namespace foveart::gpu
