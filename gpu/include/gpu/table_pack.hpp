// A view's foveation tables cut into GPU buffers (docs/gpu.md): the layout
// shaders/gather.comp reads, in 32-bit words. Pure C++: no Vulkan here.
//
// The canvas is cut at 8x8 tile rows into chunks of at most max_chunk_bytes
// (a device's maxStorageBufferRange), so a workgroup (one tile) reads one
// chunk. Each chunk starts with a 16-word header (ChunkHeader) followed by
// its sections, all offsets rebased to the chunk:
//   weighted methods: per tile (first block | level << 30), per block + 1 the
//     palette offset, the palette, the 1-byte taps and the f16/f32 weights
//     (foveation/gather_layout.hpp, interpolation_table.hpp);
//   NN: the neighbour table's 24-bit indices of the chunk's canvas rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "foveation/foveated_view.hpp"
#include "gpu/shader_interface/table_chunks.h"

namespace foveart::gpu {

// Word offsets in a chunk's header (gpu/shader_interface/table_chunks.h; shaders/common.glsl names them H_*).
enum ChunkHeader : std::uint32_t {
  kFirstRow = FOVEART_CHUNK_FIRST_ROW,
  kEndRow = FOVEART_CHUNK_END_ROW,
  kTileInfo = FOVEART_CHUNK_TILE_INFO,  // section offsets, in words
  kBlockPalette = FOVEART_CHUNK_BLOCK_PALETTE,
  kPalette = FOVEART_CHUNK_PALETTE,
  kSlots = FOVEART_CHUNK_SLOTS,
  kWeights = FOVEART_CHUNK_WEIGHTS,
  kNeighbors = FOVEART_CHUNK_NEIGHBORS,
  kBlockBase = FOVEART_CHUNK_BLOCK_BASE,
  kPaletteBase = FOVEART_CHUNK_PALETTE_BASE,
  kOrdinalBase = FOVEART_CHUNK_ORDINAL_BASE,
  kPixelBase = FOVEART_CHUNK_PIXEL_BASE,
  kHeaderWords = FOVEART_CHUNK_HEADER_WORDS,
};

inline constexpr std::size_t kMaxTableChunks = FOVEART_MAX_TABLE_CHUNKS;

struct TableChunk {
  std::uint32_t first_row = 0;  // canvas tile rows [first_row, end_row)
  std::uint32_t end_row = 0;
  std::vector<std::uint32_t> words;
};

struct TablePack {
  bool weighted = false;  // MSM / RBF through the gather layout; false: NN
  bool f16 = false;       // weights as IEEE half
  bool rbf = false;
  int k = 1;              // taps
  int neighbor_k = 1;     // neighbour-table entries per pixel (NN)
  int canvas_width_px = 0;
  int canvas_height_px = 0;
  std::vector<TableChunk> chunks;
  std::size_t bytes() const;
};

// Why the shaders cannot reconstruct with these tables; empty when they can
// (plain RBF without a constant term, whose gain needs per-pixel sums, stays on the CPU).
std::string tables_unsupported(const foveation::ViewTables& tables);

// The chunks of `tables`; false with *error when they are unsupported or a
// tile row does not fit max_chunk_bytes, or more than kMaxTableChunks are needed.
[[nodiscard]] bool pack_tables(const foveation::ViewTables& tables, std::size_t max_chunk_bytes, TablePack* out,
                     std::string* error);

}  // namespace foveart::gpu
