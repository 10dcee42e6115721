// Builds scenes in code from quads, boxes and UV spheres: the built-in
// default scene and the procedural benchmark scenes. Units are metres, +y up.
#pragma once

#include <engine/scene.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdint>
#include <utility>

namespace foveart::engine {

class Builder {
 public:
  explicit Builder(Scene& s) : s_(s) {}

  uint32_t material(Material m) {
    s_.materials.push_back(std::move(m));
    return static_cast<uint32_t>(s_.materials.size() - 1);
  }

  // Quad p0-p1-p2-p3 counter-clockwise seen from the front; uv spans [0,u]x[0,v].
  void quad(glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3, uint32_t mat, float u = 1.0f,
            float v = 1.0f) {
    const glm::vec3 n = glm::normalize(glm::cross(p1 - p0, p3 - p0));
    const uint32_t b = vertex(p0, n, {0.0f, v});
    vertex(p1, n, {u, v});
    vertex(p2, n, {u, 0.0f});
    vertex(p3, n, {0.0f, 0.0f});
    tri(b, b + 1, b + 2, mat);
    tri(b, b + 2, b + 3, mat);
  }

  void box(glm::vec3 lo, glm::vec3 hi, uint32_t mat, float uv_per_m = 1.0f) {
    const glm::vec3 d = hi - lo;
    const float su = uv_per_m;
    quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}, mat, d.x * su, d.y * su);  // +z
    quad({hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, mat, d.x * su, d.y * su);  // -z
    quad({hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, mat, d.z * su, d.y * su);  // +x
    quad({lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z}, mat, d.z * su, d.y * su);  // -x
    quad({lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}, mat, d.x * su, d.z * su);  // +y
    quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}, mat, d.x * su, d.z * su);  // -y
  }

  void sphere(glm::vec3 c, float r, uint32_t mat, int slices = 48, int stacks = 24) {
    const uint32_t base = static_cast<uint32_t>(s_.mesh.positions.size());
    for (int i = 0; i <= stacks; ++i) {
      const float theta = glm::pi<float>() * static_cast<float>(i) / static_cast<float>(stacks);
      for (int j = 0; j <= slices; ++j) {
        const float phi = glm::two_pi<float>() * static_cast<float>(j) / static_cast<float>(slices);
        const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
        vertex(c + r * n, n, {static_cast<float>(j) / static_cast<float>(slices),
                              static_cast<float>(i) / static_cast<float>(stacks)});
      }
    }
    const uint32_t row = static_cast<uint32_t>(slices + 1);
    for (uint32_t i = 0; i < static_cast<uint32_t>(stacks); ++i)
      for (uint32_t j = 0; j < static_cast<uint32_t>(slices); ++j) {
        const uint32_t a = base + i * row + j;
        const uint32_t b = a + row;
        if (i != 0) tri(a, b, a + 1, mat);
        if (i + 1 != static_cast<uint32_t>(stacks)) tri(a + 1, b, b + 1, mat);
      }
  }

  uint32_t texture(Texture t) {
    s_.textures.push_back(std::move(t));
    return static_cast<uint32_t>(s_.textures.size() - 1);
  }

 private:
  uint32_t vertex(glm::vec3 p, glm::vec3 n, glm::vec2 uv) {
    s_.mesh.positions.push_back(p);
    s_.mesh.normals.push_back(n);
    s_.mesh.uv0.push_back(uv);
    return static_cast<uint32_t>(s_.mesh.positions.size() - 1);
  }
  void tri(uint32_t a, uint32_t b, uint32_t c, uint32_t mat) {
    s_.mesh.triangles.emplace_back(a, b, c);
    s_.mesh.triangle_material.push_back(mat);
  }
  Scene& s_;
};

}  // namespace foveart::engine
