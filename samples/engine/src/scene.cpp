// Scene helpers: bounds, framing camera, effect derivation.
#include <engine/effects.hpp>
#include <engine/scene.hpp>

#include <foveation/eye_view_check.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace foveart::engine {

bool prepare_scene(Scene& scene, std::string* error) {
  const auto fail = [&](const std::string& what) {
    if (error) *error = scene.source + ": " + what;
    return false;
  };
  const Mesh& m = scene.mesh;
  const size_t nv = m.positions.size();
  if (m.triangle_material.size() != m.triangles.size() || m.normals.size() != nv ||
      (!m.uv0.empty() && m.uv0.size() != nv) || (!m.uv1.empty() && m.uv1.size() != nv))
    return fail("inconsistent mesh arrays");
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const glm::uvec3 t = m.triangles[i];
    if (t.x >= nv || t.y >= nv || t.z >= nv || m.triangle_material[i] >= scene.materials.size())
      return fail("triangle " + std::to_string(i) + " refers past the vertex or material arrays");
  }
  for (size_t i = 0; i < nv; ++i) {
    if (foveation::traceable_position(m.positions[i])) continue;
    const glm::vec3 p = m.positions[i];
    std::ostringstream what;
    what << "vertex " << i << " at (" << p.x << ", " << p.y << ", " << p.z << ") m is not finite or lies beyond "
         << foveation::kMaxPositionM << " m of the origin";
    return fail(what.str());
  }
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture& t = scene.textures[i];
    if (t.width == 0 || t.height == 0 || t.texels.size() != static_cast<size_t>(t.width) * t.height)
      return fail("texture " + std::to_string(i) + " has no or the wrong number of texels");
  }
  for (Material& mat : scene.materials)  // a texture index that does not exist is no texture
    if (mat.base_color_texture >= static_cast<int>(scene.textures.size())) mat.base_color_texture = -1;
  return true;
}

Bounds scene_bounds(const Mesh& mesh) {
  Bounds b;
  if (mesh.positions.empty()) return b;
  b.min = b.max = mesh.positions.front();
  for (const glm::vec3& p : mesh.positions) {
    b.min = glm::min(b.min, p);
    b.max = glm::max(b.max, p);
  }
  return b;
}

Camera framing_camera(const Scene& scene) {
  const Bounds b = scene_bounds(scene.mesh);
  const glm::vec3 centre = 0.5f * (b.min + b.max);
  const float radius = std::max(0.5f * glm::length(b.max - b.min), 1e-3f);
  Camera c;
  c.yfov_rad = 1.5f;  // about the FOVE vertical field of view
  // Far enough that the bounding sphere fits in the vertical field of view.
  c.position_m = centre + glm::vec3(0.0f, 0.0f, radius / std::sin(0.5f * c.yfov_rad) * 1.05f);
  c.orientation = glm::quat(1.0f, 0.0f, 0.0f, 0.0f);  // looking down -z at the centre
  return c;
}

Camera standing_viewer(const Camera& base, std::optional<glm::vec3> position_m, std::optional<glm::vec3> look_at_m) {
  Camera c = base;
  if (position_m) c.position_m = *position_m;
  if (look_at_m && glm::length(*look_at_m - c.position_m) > 1e-6f) {
    const glm::vec3 f = glm::normalize(*look_at_m - c.position_m);  // forward; the camera looks down -z
    const float yaw = std::atan2(-f.x, -f.z);
    const float pitch = std::asin(std::clamp(f.y, -1.0f, 1.0f));
    c.orientation = glm::angleAxis(yaw, glm::vec3(0.0f, 1.0f, 0.0f)) * glm::angleAxis(pitch, glm::vec3(1.0f, 0.0f, 0.0f));
  }
  return c;
}

Effects derive_effects(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (uint32_t m : scene.mesh.triangle_material)
    if (m < used.size()) used[m] = true;
  Effects e;
  e.shadows = !scene.lights.empty();
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    e.reflection = e.reflection || m.reflective();
    e.refraction = e.refraction || m.transmissive();
    if (m.base_color_texture >= 0 && static_cast<size_t>(m.base_color_texture) < scene.textures.size()) {
      const bool has_uv = m.base_color_texcoord == 0 ? !scene.mesh.uv0.empty() : !scene.mesh.uv1.empty();
      e.textures = e.textures || has_uv;
    }
  }
  return e;
}

std::string to_string(const Effects& e) {
  std::string s;
  auto add = [&s](bool on, const char* name) {
    if (!on) return;
    if (!s.empty()) s += '+';
    s += name;
  };
  add(e.shadows, "shadows");
  add(e.reflection, "reflection");
  add(e.refraction, "refraction");
  add(e.textures, "textures");
  return s.empty() ? "primary-only" : s;
}

std::optional<Effects> parse_effects(const std::string& names, std::string* error) {
  constexpr const char* kKnown = " (shadows, reflection, refraction, textures or primary-only)";
  if (names == "primary-only") return Effects::none();
  Effects e;
  std::size_t begin = 0;
  while (true) {  // each name up to the next ',' or '+', the last one up to the end
    const std::size_t end = std::min(names.find_first_of(",+", begin), names.size());
    const std::string name = names.substr(begin, end - begin);
    if (name == "shadows") e.shadows = true;
    else if (name == "reflection") e.reflection = true;
    else if (name == "refraction") e.refraction = true;
    else if (name == "textures") e.textures = true;
    else {
      *error = name.empty() ? "an empty effect name in '" + names + "'" + kKnown
                            : "unknown effect '" + name + "'" + kKnown;
      return std::nullopt;
    }
    if (end == names.size()) return e;
    begin = end + 1;
  }
}

}  // namespace foveart::engine
