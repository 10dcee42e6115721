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

// The points of one set as they are placed: the pixel grid, then Bridson's
// dart throwing from its rim outwards, then the whole set in Hilbert order.
class PointSampler {
 public:
  PointSampler(const DisplayModel& display, std::uint64_t seed)
      : display_(display),
        canvas_w_(display.canvas_width_px()),
        canvas_h_(display.canvas_height_px()),
        width_(float(canvas_w_)),
        height_(float(canvas_h_)),
        centre_{float(display.width_px), float(display.height_px)},
        radius_(display, std::hypot(double(width_), double(height_))),
        // Any conflicting point lies within min_distance(r, r_local) <= r + r_max;
        // r grows by far less than 1 px per px, so 2 r_max + 1 further out bounds it.
        reach_px_(2.0f * radius_.max() + 1.0f),
        pixel_grid_(display.fovea_pattern == FoveaPattern::kPixelGrid),
        grid_{canvas_w_, canvas_h_},
        // Pixel-grid pattern: canvas pixels holding a point; a Poisson point never
        // shares one, so no region holds more points than pixels.
        occupied_(pixel_grid_ ? std::size_t(canvas_w_) * std::size_t(canvas_h_) : 0, 0),
        rng_(detail::mix64(seed)) {}

  // The pixel grid: every canvas pixel whose centre lies within the radius
  // where f_c >= f_d (eqs. 2-4). Returns the points that seed Bridson: the
  // grid's rim, or a point at the centre when there is no grid.
  std::vector<int> place_pixel_grid() {
    std::vector<int> active;
    if (const double grid_radius_px = display_.pixel_grid_radius_px(); grid_radius_px > 0.0) {
      constexpr double kRimPx = 1.5;  // grid points this close to the edge seed Bridson
      const double r = std::min(grid_radius_px, std::hypot(double(width_), double(height_)));
      const double cx = double(centre_.x), cy = double(centre_.y);
      const int y0 = std::max(0, int(std::floor(cy - r))), y1 = std::min(canvas_h_, int(std::ceil(cy + r)) + 1);
      const int x0 = std::max(0, int(std::floor(cx - r))), x1 = std::min(canvas_w_, int(std::ceil(cx + r)) + 1);
      for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
          const double dx = double(x) + 0.5 - cx, dy = double(y) + 0.5 - cy;
          const double d = std::sqrt(dx * dx + dy * dy);
          if (d > grid_radius_px) continue;
          if (d > grid_radius_px - kRimPx) active.push_back(int(pos_.size()));
          add({float(x) + 0.5f, float(y) + 0.5f}, float(kPixelDiscRadiusPx), PointFootprint::kPixel);
        }
      }
    }
    if (pos_.empty()) {
      try_add(centre_);
      active.push_back(0);
    }
    return active;
  }

  // Bridson: around a random active point, up to k candidates in the annulus
  // [d, 2d]; the first that fits becomes active, and a point none fits around retires.
  void place_poisson_discs(std::vector<int>& active, const ProgressFn& progress) {
    std::size_t retired = 0;
    while (!active.empty()) {
      const std::size_t slot = std::size_t(rng_() % active.size());
      const int i = active[slot];
      const glm::vec2 pi = pos_[std::size_t(i)];
      const float ri = rad_[std::size_t(i)];
      bool placed = false;
      for (int c = 0; c < kCandidatesPerPoint && !placed; ++c) {
        // Annulus [d, 2d] with d the allowed distance, uniform by area (Bridson 2007).
        const float inner = min_point_distance_px(display_.disc_rule, ri, ri);
        const float outer = 2.0f * inner;
        const float dist = std::sqrt(inner * inner + uniform() * (outer * outer - inner * inner));
        const float angle = 2.0f * std::numbers::pi_v<float> * uniform();
        const glm::vec2 p = pi + dist * glm::vec2(std::cos(angle), std::sin(angle));
        if (try_add(p)) {
          active.push_back(int(pos_.size() - 1));
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
  }

  // Hilbert order for memory locality and compact ray packets (the thesis's 4.1
  // uses Morton order); ties broken by position.
  PointSet in_hilbert_order() const {
    std::vector<std::uint32_t> order(pos_.size());
    std::vector<std::uint32_t> code(pos_.size());
    for (std::size_t i = 0; i < pos_.size(); ++i) {
      order[i] = std::uint32_t(i);
      code[i] = hilbert_index(std::uint32_t(pos_[i].x), std::uint32_t(pos_[i].y));
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      if (code[a] != code[b]) return code[a] < code[b];
      if (pos_[a].y != pos_[b].y) return pos_[a].y < pos_[b].y;
      return pos_[a].x < pos_[b].x;
    });
    PointSet out;
    out.canvas_width_px = canvas_w_;
    out.canvas_height_px = canvas_h_;
    out.visible_margin_px = pixel_grid_ ? 0.0f : kVisibleMarginPx;
    out.exact_fovea_radius_px = float(display_.exact_fovea_radius_px());
    out.view_distance_px = float(display_.view_distance_px);
    out.position_px.resize(pos_.size());
    out.radius_px.resize(pos_.size());
    if (pixel_grid_) out.footprint.resize(pos_.size());
    for (std::size_t i = 0; i < order.size(); ++i) {
      out.position_px[i] = pos_[order[i]];
      out.radius_px[i] = rad_[order[i]];
      if (pixel_grid_) out.footprint[i] = foot_[order[i]];
    }
    return out;
  }

 private:
  std::size_t cell(glm::vec2 p) const { return std::size_t(p.y) * std::size_t(canvas_w_) + std::size_t(p.x); }
  float uniform() { return float(detail::unit_double(rng_())); }

  void add(glm::vec2 p, float r, PointFootprint f) {
    grid_.insert(int(pos_.size()), p);
    pos_.push_back(p);
    rad_.push_back(r);
    foot_.push_back(f);
    if (pixel_grid_) occupied_[cell(p)] = 1;
  }

  // Adds a disc at p if it lies on the canvas and keeps its distance to every point.
  bool try_add(glm::vec2 p) {
    if (p.x < 0.0f || p.y < 0.0f || p.x >= width_ || p.y >= height_) return false;
    if (pixel_grid_ && occupied_[cell(p)] != 0) return false;
    const float d = glm::length(p - centre_);
    const float r = radius_.at(d);
    const float search = min_point_distance_px(display_.disc_rule, r, radius_.at(d + reach_px_));
    if (!grid_.is_free(p, r, search, display_.disc_rule, pos_, rad_)) return false;
    add(p, r, PointFootprint::kDisc);
    return true;
  }

  const DisplayModel& display_;
  const int canvas_w_, canvas_h_;
  const float width_, height_;
  const glm::vec2 centre_;
  const RadiusProfile radius_;
  const float reach_px_;
  const bool pixel_grid_;
  PointGrid grid_;
  std::vector<std::uint8_t> occupied_;
  std::mt19937_64 rng_;
  std::vector<glm::vec2> pos_;
  std::vector<float> rad_;
  std::vector<PointFootprint> foot_;
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
  PointSampler sampler(display, seed);
  std::vector<int> active = sampler.place_pixel_grid();
  sampler.place_poisson_discs(active, progress);
  PointSet out = sampler.in_hilbert_order();
  if (progress) progress(1.0);
  return out;
}

}  // namespace foveart::foveation
