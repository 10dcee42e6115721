// The built-in default scene (see default_scene.hpp), built from quads, boxes
// and a UV sphere. Units are metres; +y up; the viewer stands at z = +3 and
// looks down -z along a hall whose far wall glows.
#include <engine/default_scene.hpp>

#include "scene_builder.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>

namespace foveart::engine {
namespace {

Texture checker_texture() {
  Texture t;
  t.width = t.height = 64;
  t.texels.resize(64 * 64);
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      const bool dark = ((x / 32) + (y / 32)) % 2 == 1;
      t.texels[y * 64 + x] = dark ? glm::vec4(0.08f, 0.08f, 0.09f, 1.0f) : glm::vec4(0.75f, 0.72f, 0.66f, 1.0f);
    }
  return t;
}

Texture brick_texture() {
  Texture t;
  t.width = 128;
  t.height = 64;
  t.texels.resize(128 * 64);
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 128; ++x) {
      const uint32_t course = y / 16;
      const uint32_t xs = (x + (course % 2) * 16) % 32;
      const bool mortar = (y % 16) < 2 || xs < 2;
      // A little per-brick variation so the texture has structure at every scale.
      const float shade = 0.85f + 0.15f * static_cast<float>(((x + (course % 2) * 16) / 32 * 7 + course * 3) % 5) / 4.0f;
      t.texels[y * 128 + x] = mortar ? glm::vec4(0.55f, 0.55f, 0.52f, 1.0f)
                                     : glm::vec4(0.45f * shade, 0.16f * shade, 0.10f * shade, 1.0f);
    }
  return t;
}

constexpr float kColonnadeZ = -6.0f;
constexpr float kGlassRadius = 0.7f;

constexpr float kHallHeight = 4.0f;

// The scene's materials, by their index in the scene.
struct SceneMaterials {
  uint32_t floor, wall, ceiling, glow, panel, pillar, glass, crate;
};

SceneMaterials add_materials(Builder& b) {
  const uint32_t checker = b.texture(checker_texture());
  const uint32_t brick = b.texture(brick_texture());

  Material floor;  // polished checker floor: textured and mirror-like
  floor.name = "polished floor";
  floor.base_color_texture = static_cast<int>(checker);
  floor.metallic = 0.25f;
  floor.roughness = 0.1f;
  Material wall;
  wall.name = "brick wall";
  wall.base_color_texture = static_cast<int>(brick);
  wall.metallic = 0.0f;
  wall.roughness = 0.9f;
  Material ceiling;
  ceiling.name = "ceiling";
  ceiling.base_color = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
  ceiling.metallic = 0.0f;
  ceiling.roughness = 1.0f;
  Material glow;  // the bright far wall: the background the pillars stand against
  glow.name = "bright far wall";
  glow.base_color = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
  glow.emissive = glm::vec3(3.0f, 2.9f, 2.7f);
  glow.metallic = 0.0f;
  Material panel;
  panel.name = "ceiling light panel";
  panel.base_color = glm::vec4(1.0f);
  panel.emissive = glm::vec3(12.0f, 11.5f, 10.5f);
  panel.metallic = 0.0f;
  Material pillar;
  pillar.name = "dark pillar";
  pillar.base_color = glm::vec4(0.03f, 0.03f, 0.035f, 1.0f);
  pillar.metallic = 0.0f;
  pillar.roughness = 0.8f;
  Material glass;
  glass.name = "glass";
  glass.base_color = glm::vec4(0.95f, 0.98f, 1.0f, 1.0f);
  glass.metallic = 0.0f;
  glass.roughness = 0.0f;
  glass.transmission = 1.0f;
  glass.ior = 1.5f;
  Material crate;
  crate.name = "checker crate";
  crate.base_color_texture = static_cast<int>(checker);
  crate.base_color = glm::vec4(0.9f, 0.6f, 0.3f, 1.0f);
  crate.metallic = 0.0f;
  crate.roughness = 0.7f;

  return {b.material(floor), b.material(wall),   b.material(ceiling), b.material(glow),
          b.material(panel), b.material(pillar), b.material(glass),   b.material(crate)};
}

// Floor, ceiling and walls; the far wall glows, with a gap around it that shows the bright sky.
void add_hall(Builder& b, const SceneMaterials& m) {
  const float x0 = -5.0f, x1 = 5.0f, z0 = -18.0f, z1 = 5.0f, h = kHallHeight;
  b.quad({x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}, {x0, 0, z0}, m.floor, 10.0f, 23.0f);  // floor, 1 m checks
  b.quad({x0, h, z0}, {x1, h, z0}, {x1, h, z1}, {x0, h, z1}, m.ceiling);              // ceiling
  b.quad({x0, 0, z1}, {x0, 0, z0}, {x0, h, z0}, {x0, h, z1}, m.wall, 23.0f, 4.0f);    // left wall
  b.quad({x1, 0, z0}, {x1, 0, z1}, {x1, h, z1}, {x1, h, z0}, m.wall, 23.0f, 4.0f);    // right wall
  b.quad({x0 + 0.5f, 0.0f, z0}, {x1 - 0.5f, 0.0f, z0}, {x1 - 0.5f, h - 0.5f, z0}, {x0 + 0.5f, h - 0.5f, z0},
         m.glow);  // bright far wall; the gap around it shows the bright sky
  b.quad({x1, 0, z1}, {x0, 0, z1}, {x0, h, z1}, {x1, h, z1}, m.wall, 10.0f, 4.0f);  // wall behind the viewer
}

void add_pillars(Builder& b, const SceneMaterials& m) {
  const float h = kHallHeight;
  for (int i = 0; i < 6; ++i) {  // two rows of dark pillars against the bright wall
    const float z = -2.0f - 2.6f * static_cast<float>(i);
    b.box({-2.6f, 0.0f, z - 0.2f}, {-2.2f, h, z + 0.2f}, m.pillar);
    b.box({2.2f, 0.0f, z - 0.2f}, {2.6f, h, z + 0.2f}, m.pillar);
  }
  // The cross colonnade the view centre looks through: two dark pillars either
  // side of the centre line, 0.4 m apart, seen against the glowing far wall.
  b.box({-0.6f, 0.0f, kColonnadeZ - 0.2f}, {-0.2f, h, kColonnadeZ + 0.2f}, m.pillar);
  b.box({0.2f, 0.0f, kColonnadeZ - 0.2f}, {0.6f, h, kColonnadeZ + 0.2f}, m.pillar);
}

void add_ceiling_lights(Builder& b, const SceneMaterials& m, Scene& s) {
  const float h = kHallHeight;
  for (int i = 0; i < 4; ++i) {  // bright ceiling light panels, each with a point light below
    const float z = -1.0f - 4.0f * static_cast<float>(i);
    b.quad({-0.8f, h - 0.01f, z - 0.4f}, {0.8f, h - 0.01f, z - 0.4f}, {0.8f, h - 0.01f, z + 0.4f},
           {-0.8f, h - 0.01f, z + 0.4f}, m.panel);
    Light l;
    l.type = LightType::kPoint;
    l.position = glm::vec3(0.0f, h - 0.3f, z);
    l.color = glm::vec3(1.0f, 0.96f, 0.9f);
    l.intensity = 14.0f;
    s.lights.push_back(l);
  }
}

}  // namespace

DefaultSceneLandmarks default_scene_landmarks() {
  DefaultSceneLandmarks m;
  m.pillar_edge = glm::vec3(-0.2f, 1.6f, kColonnadeZ + 0.2f);
  m.glass_centre = glm::vec3(-3.0f, kGlassRadius, -1.0f);
  m.floor_point = glm::vec3(0.0f, 0.0f, 1.4f);
  return m;
}

Scene make_default_scene() {
  Scene s;
  s.source = "default";
  s.sky_zenith = glm::vec3(2.0f, 2.0f, 2.1f);  // bright openings behind the far wall edges
  s.sky_horizon = glm::vec3(1.6f, 1.6f, 1.7f);
  s.ambient = glm::vec3(0.06f);
  Builder b(s);
  const SceneMaterials m = add_materials(b);
  add_hall(b, m);
  add_pillars(b, m);
  add_ceiling_lights(b, m, s);
  const DefaultSceneLandmarks marks = default_scene_landmarks();
  b.sphere(marks.glass_centre, kGlassRadius, m.glass);  // far left of the view, between the left pillars and the wall
  b.box({0.9f, 0.0f, -2.2f}, {1.7f, 0.8f, -1.4f}, m.crate, 2.0f);

  Camera cam;
  cam.position_m = glm::vec3(0.0f, 1.6f, 3.0f);
  cam.yfov_rad = 1.6f;
  s.camera = cam;
  return s;
}

}  // namespace foveart::engine
