#include "foveation/gather_layout.hpp"

#include <algorithm>
#include <stdexcept>

namespace foveart::foveation {

static_assert(kMaxNeighbors <= 256, "1x1 blocks must fit a 256-entry palette");

namespace {

// One tile row's palettes, offsets relative to the row (merged in order).
struct RowLayout {
  std::vector<std::uint8_t> level;
  std::vector<std::uint32_t> blocks;   // blocks per tile
  std::vector<std::uint32_t> sizes;    // palette size per block
  std::vector<std::uint32_t> palette;  // concatenated
};

struct TileGeom {
  int x0, y0, tw, th;
};

// Per-thread scratch: which points the current block already holds (a stamp
// per point instead of sorting every tap) and their slots.
struct Dedup {
  std::vector<std::uint32_t> stamp;
  std::vector<std::uint8_t> pos;
  std::uint32_t gen = 0;
};

// Palette of one block (distinct point indices of its taps, ascending) appended
// to `out`, and every tap's slot written; false when more than 256 points.
bool build_block(const NeighborTable& nt, int k, const TileGeom& g, int bx0, int by0, int bx1, int by1, Dedup& d,
                 GatherLayout& l, std::vector<std::uint32_t>& out) {
  if (++d.gen == 0) {  // stamps wrapped: forget them all
    std::fill(d.stamp.begin(), d.stamp.end(), 0u);
    d.gen = 1;
  }
  const std::size_t start = out.size();
  for (int ly = by0; ly < by1; ++ly) {
    for (int lx = bx0; lx < bx1; ++lx) {
      const std::size_t p = std::size_t(g.y0 + ly) * std::size_t(nt.width_px()) + std::size_t(g.x0 + lx);
      for (int j = 0; j < k; ++j) {
        const std::uint32_t id = nt.neighbor(p, j);
        if (id >= d.stamp.size()) {
          d.stamp.resize(std::max<std::size_t>(id + 1, d.stamp.size() * 2), 0u);
          d.pos.resize(d.stamp.size(), 0);
        }
        if (d.stamp[id] == d.gen) continue;
        if (out.size() - start == 256) {
          out.resize(start);
          return false;
        }
        d.stamp[id] = d.gen;
        out.push_back(id);
      }
    }
  }
  std::sort(out.begin() + std::ptrdiff_t(start), out.end());
  for (std::size_t i = start; i < out.size(); ++i) d.pos[out[i]] = std::uint8_t(i - start);
  for (int ly = by0; ly < by1; ++ly) {
    for (int lx = bx0; lx < bx1; ++lx) {
      const std::size_t p = std::size_t(g.y0 + ly) * std::size_t(nt.width_px()) + std::size_t(g.x0 + lx);
      std::uint8_t* slot = l.slot.data() + tile_ordinal(l.width_px, l.height_px, g.x0 + lx, g.y0 + ly) * std::size_t(k);
      for (int j = 0; j < k; ++j) slot[j] = d.pos[nt.neighbor(p, j)];
    }
  }
  return true;
}

void build_tile_row(const NeighborTable& nt, int k, int ty, GatherLayout& l, Dedup& d, RowLayout& row) {
  const int y0 = ty * kGatherTilePx;
  const int th = std::min(kGatherTilePx, l.height_px - y0);
  std::vector<std::uint32_t> sizes;
  for (int tx = 0; tx < l.tiles_x(); ++tx) {
    const TileGeom g{tx * kGatherTilePx, y0, std::min(kGatherTilePx, l.width_px - tx * kGatherTilePx), th};
    for (int level = 0; level < 4; ++level) {  // level 3 (1x1 blocks) always fits: k <= kMaxNeighbors
      const int bs = kGatherTilePx >> level;
      const std::size_t palette_mark = row.palette.size();
      sizes.clear();
      bool fits = true;
      for (int by = 0; by < g.th && fits; by += bs) {
        for (int bx = 0; bx < g.tw && fits; bx += bs) {
          const std::size_t before = row.palette.size();
          fits = build_block(nt, k, g, bx, by, std::min(g.tw, bx + bs), std::min(g.th, by + bs), d, l, row.palette);
          sizes.push_back(std::uint32_t(row.palette.size() - before));
        }
      }
      if (!fits) {
        row.palette.resize(palette_mark);
        continue;
      }
      row.level.push_back(std::uint8_t(level));
      row.blocks.push_back(std::uint32_t(sizes.size()));
      row.sizes.insert(row.sizes.end(), sizes.begin(), sizes.end());
      break;
    }
  }
}

}  // namespace

GatherLayout build_gather_layout(const NeighborTable& nt, int k, Executor& executor) {
  if (k < 1 || k > nt.k()) {
    throw std::invalid_argument("gather layout: k = " + std::to_string(k) + " outside 1.." + std::to_string(nt.k()));
  }
  GatherLayout l;
  l.width_px = nt.width_px();
  l.height_px = nt.height_px();
  l.k = k;
  l.slot.assign(std::size_t(l.width_px) * std::size_t(l.height_px) * std::size_t(k), 0);
  const int rows = l.tiles_y();
  auto row = std::vector<RowLayout>(std::size_t(rows));
  std::vector<Dedup> dedup(executor.thread_count());  // per worker slot
  executor.parallel_for(std::size_t(rows), [&](std::size_t ty, unsigned worker) {
    build_tile_row(nt, k, int(ty), l, dedup[worker], row[ty]);
  });
  l.tile_first_block.push_back(0);
  l.block_palette.push_back(0);
  for (const auto& r : row) {
    l.tile_level.insert(l.tile_level.end(), r.level.begin(), r.level.end());
    for (std::uint32_t n : r.blocks) l.tile_first_block.push_back(l.tile_first_block.back() + n);
    for (std::uint32_t n : r.sizes) l.block_palette.push_back(l.block_palette.back() + n);
    l.palette.insert(l.palette.end(), r.palette.begin(), r.palette.end());
  }
  return l;
}

std::string gather_layout_error(const GatherLayout& l, int width_px, int height_px, int k, std::size_t point_count) {
  if (l.width_px != width_px || l.height_px != height_px || l.k != k) return "gather layout is for another canvas or k";
  const std::size_t tiles = std::size_t(l.tiles_x()) * std::size_t(l.tiles_y());
  if (l.tile_level.size() != tiles || l.tile_first_block.size() != tiles + 1 ||
      l.slot.size() != std::size_t(width_px) * std::size_t(height_px) * std::size_t(k) || l.block_palette.empty() ||
      l.tile_first_block.front() != 0 || l.tile_first_block.back() + 1 != l.block_palette.size() ||
      l.block_palette.front() != 0 || l.block_palette.back() != l.palette.size()) {
    return "gather layout sizes do not match the canvas";
  }
  for (std::size_t b = 0; b + 1 < l.block_palette.size(); ++b) {
    if (l.block_palette[b + 1] < l.block_palette[b] || l.block_palette[b + 1] - l.block_palette[b] > 256) {
      return "gather layout block " + std::to_string(b) + " has a bad palette range";
    }
  }
  for (std::uint32_t p : l.palette) {
    if (p >= point_count) return "gather layout palette entry " + std::to_string(p) + " is not a point index";
  }
  for (int ty = 0; ty < l.tiles_y(); ++ty) {
    for (int tx = 0; tx < l.tiles_x(); ++tx) {
      const std::size_t t = std::size_t(ty) * std::size_t(l.tiles_x()) + std::size_t(tx);
      const int level = l.tile_level[t];
      if (level > 3) return "gather layout tile " + std::to_string(t) + " has level " + std::to_string(level);
      const int bs = kGatherTilePx >> level;
      const int tw = std::min(kGatherTilePx, width_px - tx * kGatherTilePx);
      const int th = std::min(kGatherTilePx, height_px - ty * kGatherTilePx);
      const int nbx = (tw + bs - 1) / bs, nby = (th + bs - 1) / bs;
      if (l.tile_first_block[t + 1] < l.tile_first_block[t] ||
          l.tile_first_block[t + 1] - l.tile_first_block[t] != std::uint32_t(nbx * nby)) {
        return "gather layout tile " + std::to_string(t) + " has the wrong block count";
      }
      for (int ly = 0; ly < th; ++ly) {
        for (int lx = 0; lx < tw; ++lx) {
          const std::size_t b = l.tile_first_block[t] + std::size_t((ly / bs) * nbx + lx / bs);
          const std::uint32_t size = l.block_palette[b + 1] - l.block_palette[b];
          const std::uint8_t* s =
              l.slot.data() + tile_ordinal(width_px, height_px, tx * kGatherTilePx + lx, ty * kGatherTilePx + ly) *
                                  std::size_t(k);
          for (int j = 0; j < k; ++j) {
            if (s[j] >= size) return "gather layout slot outside its palette in tile " + std::to_string(t);
          }
        }
      }
    }
  }
  return {};
}

}  // namespace foveart::foveation
