// The perceptual point set (thesis 4.1): the pixel grid where the eye resolves
// every pixel, then adaptive Poisson-disc points by variable-radius Bridson
// sampling (Bridson 2007) under the display's DiscRule.
#include "foveation/point_set.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>

#include <glm/geometric.hpp>

#include "foveation/display_model.hpp"
#include "hash.hpp"

namespace foveart::foveation {
namespace {

// Bridson's k: candidates tried around an active point before it retires.
constexpr int kCandidatesPerPoint = 30;
constexpr float kGridCellPx = 2.0f;

// Radius as a function of distance to the centre of interest, tabulated at
// 1/8 px so the sampler's hot loop avoids atan/log. Monotonic non-decreasing.
class RadiusProfile {
 public:
  RadiusProfile(const DisplayModel& display, double max_distance_px) {
    const std::size_t n = std::size_t(max_distance_px * double(kStepsPerPx)) + 2;
    radius_.resize(n);
    for (std::size_t i = 0; i < n; ++i) radius_[i] = float(display.radius_px(double(i) / double(kStepsPerPx)));
    // Exact at the dart: interpolate; guard monotonicity for the search bound.
    for (std::size_t i = 1; i < n; ++i) radius_[i] = std::max(radius_[i], radius_[i - 1]);
  }
  float at(float distance_px) const {
    const float f = std::min(distance_px * kStepsPerPx, float(radius_.size() - 2));
    const std::size_t i = std::size_t(f);
    const float t = f - float(i);
    return radius_[i] + t * (radius_[i + 1] - radius_[i]);
  }
  float max() const { return radius_.back(); }

 private:
  static constexpr float kStepsPerPx = 8.0f;
  std::vector<float> radius_;
};

// Uniform grid of linked lists: head per cell, next per point.
class PointGrid {
 public:
  PointGrid(int width_px, int height_px)
      : cols_(int(std::ceil(float(width_px) / kGridCellPx))),
        rows_(int(std::ceil(float(height_px) / kGridCellPx))),
        head_(std::size_t(cols_) * std::size_t(rows_), -1) {}

  void insert(int index, glm::vec2 p) {
    const std::size_t c = cell(p);
    if (std::size_t(index) >= next_.size()) next_.resize(std::size_t(index) + 1, -1);
    next_[std::size_t(index)] = head_[c];
    head_[c] = index;
  }

  // True when no stored point j is closer than the rule allows; search_px bounds that distance.
  bool is_free(glm::vec2 p, float r, float search_px, DiscRule rule, const std::vector<glm::vec2>& pos,
               const std::vector<float>& rad) const {
    const int cx0 = std::max(0, int((p.x - search_px) / kGridCellPx));
    const int cx1 = std::min(cols_ - 1, int((p.x + search_px) / kGridCellPx));
    const int cy0 = std::max(0, int((p.y - search_px) / kGridCellPx));
    const int cy1 = std::min(rows_ - 1, int((p.y + search_px) / kGridCellPx));
    for (int cy = cy0; cy <= cy1; ++cy) {
      for (int cx = cx0; cx <= cx1; ++cx) {
        for (int j = head_[std::size_t(cy) * std::size_t(cols_) + std::size_t(cx)]; j >= 0;
             j = next_[std::size_t(j)]) {
          const glm::vec2 d = p - pos[std::size_t(j)];
          const float min_d = min_point_distance_px(rule, r, rad[std::size_t(j)]);
          if (d.x * d.x + d.y * d.y < min_d * min_d) return false;
        }
      }
    }
    return true;
  }

 private:
  std::size_t cell(glm::vec2 p) const {
    const int cx = std::clamp(int(p.x / kGridCellPx), 0, cols_ - 1);
    const int cy = std::clamp(int(p.y / kGridCellPx), 0, rows_ - 1);
    return std::size_t(cy) * std::size_t(cols_) + std::size_t(cx);
  }
  int cols_;
  int rows_;
  std::vector<int> head_;
  std::vector<int> next_;
};

}  // namespace

std::uint32_t hilbert_index(std::uint32_t x, std::uint32_t y) {
  constexpr std::uint32_t kSide = 1u << 16;
  x &= kSide - 1;
  y &= kSide - 1;
  std::uint32_t index = 0;
  for (std::uint32_t s = kSide / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (x & s) != 0, ry = (y & s) != 0;
    index += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {  // turn the quadrant so that the curve inside it runs in its canonical orientation
      if (rx == 1) {
        x = kSide - 1 - x;
        y = kSide - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return index;
}

PointSet generate_point_set(const DisplayModel& display, std::uint64_t seed, const ProgressFn& progress) {
  if (const std::string err = display.validate(); !err.empty()) throw std::invalid_argument(err);

  const int canvas_w = display.canvas_width_px();
  const int canvas_h = display.canvas_height_px();
  const float width = float(canvas_w);
  const float height = float(canvas_h);
  const glm::vec2 centre{float(display.width_px), float(display.height_px)};
  const RadiusProfile radius(display, std::hypot(double(width), double(height)));
  // Any conflicting point lies within min_distance(r, r_local) <= r + r_max;
  // r grows by far less than 1 px per px, so 2 r_max + 1 further out bounds it.
  const float reach_px = 2.0f * radius.max() + 1.0f;
  const bool pixel_grid = display.fovea_pattern == FoveaPattern::kPixelGrid;

  std::vector<glm::vec2> pos;
  std::vector<float> rad;
  std::vector<PointFootprint> foot;
  PointGrid grid{canvas_w, canvas_h};
  // Pixel-grid pattern: canvas pixels holding a point; a Poisson point never
  // shares one, so no region holds more points than pixels.
  std::vector<std::uint8_t> occupied(pixel_grid ? std::size_t(canvas_w) * std::size_t(canvas_h) : 0, 0);
  auto cell = [&](glm::vec2 p) { return std::size_t(p.y) * std::size_t(canvas_w) + std::size_t(p.x); };
  std::mt19937_64 rng(detail::mix64(seed));
  auto uniform = [&rng] { return float(detail::unit_double(rng())); };

  auto add = [&](glm::vec2 p, float r, PointFootprint f) {
    grid.insert(int(pos.size()), p);
    pos.push_back(p);
    rad.push_back(r);
    foot.push_back(f);
    if (pixel_grid) occupied[cell(p)] = 1;
  };
  auto try_add = [&](glm::vec2 p) {
    if (p.x < 0.0f || p.y < 0.0f || p.x >= width || p.y >= height) return false;
    if (pixel_grid && occupied[cell(p)] != 0) return false;
    const float d = glm::length(p - centre);
    const float r = radius.at(d);
    const float search = min_point_distance_px(display.disc_rule, r, radius.at(d + reach_px));
    if (!grid.is_free(p, r, search, display.disc_rule, pos, rad)) return false;
    add(p, r, PointFootprint::kDisc);
    return true;
  };

  // The pixel grid: every canvas pixel whose centre lies within the radius
  // where f_c >= f_d (eqs. 2-4); its rim seeds the Poisson set beyond it.
  std::vector<int> active;
  if (const double grid_radius_px = display.pixel_grid_radius_px(); grid_radius_px > 0.0) {
    constexpr double kRimPx = 1.5;  // grid points this close to the edge seed Bridson
    const double r = std::min(grid_radius_px, std::hypot(double(width), double(height)));
    const double cx = double(centre.x), cy = double(centre.y);
    const int y0 = std::max(0, int(std::floor(cy - r))), y1 = std::min(canvas_h, int(std::ceil(cy + r)) + 1);
    const int x0 = std::max(0, int(std::floor(cx - r))), x1 = std::min(canvas_w, int(std::ceil(cx + r)) + 1);
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const double dx = double(x) + 0.5 - cx, dy = double(y) + 0.5 - cy;
        const double d = std::sqrt(dx * dx + dy * dy);
        if (d > grid_radius_px) continue;
        if (d > grid_radius_px - kRimPx) active.push_back(int(pos.size()));
        add({float(x) + 0.5f, float(y) + 0.5f}, float(kPixelDiscRadiusPx), PointFootprint::kPixel);
      }
    }
  }
  if (pos.empty()) {
    try_add(centre);
    active.push_back(0);
  }

  std::size_t retired = 0;
  while (!active.empty()) {
    const std::size_t slot = std::size_t(rng() % active.size());
    const int i = active[slot];
    const glm::vec2 pi = pos[std::size_t(i)];
    const float ri = rad[std::size_t(i)];
    bool placed = false;
    for (int c = 0; c < kCandidatesPerPoint && !placed; ++c) {
      // Annulus [d, 2d] with d the allowed distance, uniform by area (Bridson 2007).
      const float inner = min_point_distance_px(display.disc_rule, ri, ri);
      const float outer = 2.0f * inner;
      const float dist = std::sqrt(inner * inner + uniform() * (outer * outer - inner * inner));
      const float angle = 2.0f * std::numbers::pi_v<float> * uniform();
      const glm::vec2 p = pi + dist * glm::vec2(std::cos(angle), std::sin(angle));
      if (try_add(p)) {
        active.push_back(int(pos.size() - 1));
        placed = true;
      }
    }
    if (!placed) {
      active[slot] = active.back();
      active.pop_back();
      if (progress && (++retired & 0x3FFFu) == 0) {
        progress(std::min(0.99, double(retired) / double(retired + active.size() * 4 + 1)));
      }
    }
  }

  // Hilbert order for memory locality and compact ray packets (the thesis's 4.1
  // uses Morton order); ties broken by position.
  std::vector<std::uint32_t> order(pos.size());
  std::vector<std::uint32_t> code(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) {
    order[i] = std::uint32_t(i);
    code[i] = hilbert_index(std::uint32_t(pos[i].x), std::uint32_t(pos[i].y));
  }
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (code[a] != code[b]) return code[a] < code[b];
    if (pos[a].y != pos[b].y) return pos[a].y < pos[b].y;
    return pos[a].x < pos[b].x;
  });

  PointSet out;
  out.canvas_width_px = canvas_w;
  out.canvas_height_px = canvas_h;
  out.visible_margin_px = pixel_grid ? 0.0f : kVisibleMarginPx;
  out.position_px.resize(pos.size());
  out.radius_px.resize(pos.size());
  if (pixel_grid) out.footprint.resize(pos.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    out.position_px[i] = pos[order[i]];
    out.radius_px[i] = rad[order[i]];
    if (pixel_grid) out.footprint[i] = foot[order[i]];
  }
  if (progress) progress(1.0);
  return out;
}

}  // namespace foveart::foveation
