#include "foveation/taa.hpp"

#include <algorithm>
#include <cmath>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

namespace foveart::foveation {

namespace {

// Rows [y0, y1): out = lerp(constrain(history), current, alpha).
void taa_rows(const ImageRgb& cur, const ImageRgb& hist, ImageRgb& out, const TaaOptions& o, int y0, int y1) {
  const int w = cur.width_px, h = cur.height_px;
  const float alpha = o.current_weight;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < w; ++x) {
      float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
      float m1[3] = {0, 0, 0}, m2[3] = {0, 0, 0};
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        const int yy = std::clamp(y + dy, 0, h - 1);
        for (int dx = -1; dx <= 1; ++dx) {
          const float* c = cur.at(std::clamp(x + dx, 0, w - 1), yy);
          for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], c[i]);
            hi[i] = std::max(hi[i], c[i]);
            m1[i] += c[i];
            m2[i] += c[i] * c[i];
          }
          ++n;
        }
      }
      const float* c = cur.at(x, y);
      const float* hp = hist.at(x, y);
      float* dst = out.at(x, y);
      float hv[3] = {hp[0], hp[1], hp[2]};
      if (o.constraint == TaaConstraint::minmax_clamp) {
        for (int i = 0; i < 3; ++i) hv[i] = std::clamp(hv[i], lo[i], hi[i]);  // Karis 2014
      } else {
        // Salvi 2016: clip the history towards the mean onto the box mu +- gamma sigma.
        float mu[3], ext[3];
        for (int i = 0; i < 3; ++i) {
          mu[i] = m1[i] / float(n);
          const float var = std::max(0.0f, m2[i] / float(n) - mu[i] * mu[i]);
          ext[i] = o.variance_gamma * std::sqrt(var) + 1e-6f;
        }
        float t = 1.0f;  // largest scale of (h - mu) that stays inside the box
        for (int i = 0; i < 3; ++i) {
          const float d = std::abs(hv[i] - mu[i]);
          if (d > ext[i]) t = std::min(t, ext[i] / d);
        }
        for (int i = 0; i < 3; ++i) hv[i] = mu[i] + (hv[i] - mu[i]) * t;
      }
      for (int i = 0; i < 3; ++i) dst[i] = hv[i] + alpha * (c[i] - hv[i]);
    }
  }
}

}  // namespace

const ImageRgb& TemporalAccumulator::accumulate(const ImageRgb& current, glm::vec2 gaze_px, bool saccade) {
  const bool size_changed = history_.width_px != current.width_px || history_.height_px != current.height_px;
  const bool jumped = valid_ && glm::distance(gaze_px, gaze_px_) > options_.reset_distance_px;
  gaze_px_ = gaze_px;
  last_reset_ = !valid_ || size_changed || jumped || saccade;
  if (last_reset_) {
    history_ = current;
    valid_ = true;
    ++resets_;
    return history_;
  }
  scratch_.width_px = current.width_px;
  scratch_.height_px = current.height_px;
  scratch_.rgb.resize(current.rgb.size());
  int threads = options_.threads > 0 ? options_.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::max(1, std::min(threads, current.height_px));
  std::vector<std::thread> pool;
  const int h = current.height_px;
  for (int i = 1; i < threads; ++i) {
    pool.emplace_back([&, i] { taa_rows(current, history_, scratch_, options_, h * i / threads, h * (i + 1) / threads); });
  }
  taa_rows(current, history_, scratch_, options_, 0, h / threads);
  for (auto& t : pool) t.join();
  std::swap(history_, scratch_);
  return history_;
}

}  // namespace foveart::foveation
