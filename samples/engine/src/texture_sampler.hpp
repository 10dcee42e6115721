// Bilinear (or nearest) texture lookup with glTF wrap modes; uv origin at the
// top-left of the image as in glTF.
#pragma once

#include <engine/scene.hpp>

#include <glm/common.hpp>

#include <cmath>

namespace foveart::engine {

inline int wrap_texel(int i, int n, WrapMode mode) {
  switch (mode) {
    case WrapMode::kClamp: return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case WrapMode::kMirror: {
      const int period = 2 * n;
      int m = i % period;
      if (m < 0) m += period;
      return m < n ? m : period - 1 - m;
    }
    case WrapMode::kRepeat:
    default: {
      int m = i % n;
      return m < 0 ? m + n : m;
    }
  }
}

inline glm::vec4 sample_texture(const Texture& t, glm::vec2 uv) {
  const int w = static_cast<int>(t.width);
  const int h = static_cast<int>(t.height);
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) uv = glm::vec2(0.0f);
  // Keep coordinates in a range where float -> int cannot overflow.
  uv = glm::clamp(uv, glm::vec2(-1.0e6f), glm::vec2(1.0e6f));
  const float x = uv.x * static_cast<float>(w) - 0.5f;
  const float y = uv.y * static_cast<float>(h) - 0.5f;
  const float fx0 = std::floor(x);
  const float fy0 = std::floor(y);
  const int x0 = static_cast<int>(fx0);
  const int y0 = static_cast<int>(fy0);
  auto at = [&](int xi, int yi) {
    return t.texels[static_cast<size_t>(wrap_texel(yi, h, t.wrap_t)) * t.width +
                    static_cast<size_t>(wrap_texel(xi, w, t.wrap_s))];
  };
  if (t.nearest) return at(static_cast<int>(std::floor(x + 0.5f)), static_cast<int>(std::floor(y + 0.5f)));
  const float ax = x - fx0;
  const float ay = y - fy0;
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), ax), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), ax), ay);
}

}  // namespace foveart::engine
