// The engine's scene: triangles flattened into tracking space, PBR
// metallic-roughness materials, textures, punctual lights, an optional camera.
// Filled by the glTF loader or the built-in default scene; read by the tracer.
#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace foveart::engine {

enum class WrapMode : uint8_t { kRepeat, kClamp, kMirror };
enum class AlphaMode : uint8_t { kOpaque, kMask, kBlend };
enum class LightType : uint8_t { kPoint, kSpot, kDirectional };

// RGBA texels already converted to linear (base colour textures are sRGB).
struct Texture {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<glm::vec4> texels;  // row-major, top row first (glTF uv origin)
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;
  bool nearest = false;
};

struct Material {
  std::string name;
  glm::vec4 base_color{1.0f};   // linear RGBA factor
  int base_color_texture = -1;  // index into Scene::textures
  int base_color_texcoord = 0;  // TEXCOORD_0 or TEXCOORD_1
  float metallic = 1.0f;        // glTF defaults
  float roughness = 1.0f;
  glm::vec3 emissive{0.0f};     // linear radiance added on hit
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;
  float transmission = 0.0f;    // KHR_materials_transmission
  float ior = 1.5f;             // KHR_materials_ior
  bool double_sided = false;

  // Mirror-like reflection: smooth surfaces (metal or dielectric).
  bool reflective() const { return roughness <= kMirrorRoughness; }
  // Rays continue through the surface: transmission or alpha blending.
  bool transmissive() const {
    return transmission > 0.0f || (alpha_mode == AlphaMode::kBlend && base_color.a < 1.0f);
  }
  static constexpr float kMirrorRoughness = 0.5f;
};

struct Light {
  LightType type = LightType::kPoint;
  glm::vec3 position{0.0f};          // point, spot
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  // spot, directional: where the light travels
  glm::vec3 color{1.0f};
  float intensity = 1.0f;            // candela (point, spot) or lux (directional)
  float range = 0.0f;                // 0 = infinite
  float inner_cone_rad = 0.0f;
  float outer_cone_rad = 0.7853982f;
};

struct Camera {
  glm::vec3 position_m{0.0f};
  glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};
  float yfov_rad = 0.8f;
  float aspect = 0.0f;  // 0 = not given
};

// Flattened triangle mesh. Arrays indexed by vertex have positions.size()
// entries; normals of zero length mean "use the geometric normal"; uv arrays
// are empty when no primitive has that texcoord set.
struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uv0;
  std::vector<glm::vec2> uv1;
  std::vector<glm::uvec3> triangles;
  std::vector<uint32_t> triangle_material;  // one per triangle
};

struct Scene {
  std::string source;  // file name or "default"
  Mesh mesh;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  std::optional<Camera> camera;
  glm::vec3 sky_zenith{0.35f, 0.45f, 0.65f};   // miss colour looking up
  glm::vec3 sky_horizon{0.75f, 0.78f, 0.82f};  // and at the horizon and below
  glm::vec3 ambient{0.15f};                    // constant ambient irradiance / pi
  std::vector<std::string> warnings;           // things loaded approximately or skipped
};

// Makes a scene ready for an engine to trace, the one check both sample
// engines run: false with *error naming the source and what is wrong when the
// mesh's arrays disagree, an index points past them, a texture lacks texels,
// or a vertex lies beyond foveation::kMaxPositionM (its hits would spawn rays
// that Embree aborts on). A texture index past the textures becomes no texture.
bool prepare_scene(Scene& scene, std::string* error);

// Axis-aligned bounds of the mesh (empty scene: both zero).
struct Bounds {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
};
Bounds scene_bounds(const Mesh& mesh);

// A camera looking at the whole scene from +z when the scene has none: a view
// from outside. A VR user stands inside a scene: standing_viewer places them.
Camera framing_camera(const Scene& scene);

// A standing viewer: `base` moved to position_m (when given) and, when look_at_m
// is given, turned upright (yaw, then pitch, no roll) to face that point (a
// point at the position itself leaves the orientation as it is).
Camera standing_viewer(const Camera& base, std::optional<glm::vec3> position_m, std::optional<glm::vec3> look_at_m);

}  // namespace foveart::engine
