// The procedural benchmark interiors (procedural_scenes.hpp).
#include <engine/procedural_scenes.hpp>

#include "scene_builder.hpp"

#include <glm/gtc/quaternion.hpp>

#include <cmath>

namespace foveart::engine {
namespace {

Material diffuse(const char* name, glm::vec3 albedo, float roughness = 0.9f) {
  Material m;
  m.name = name;
  m.base_color = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = roughness;
  return m;
}

void point_light(Scene& s, glm::vec3 position_m, float intensity_cd, glm::vec3 color = glm::vec3(1.0f)) {
  Light l;
  l.type = LightType::kPoint;
  l.position = position_m;
  l.intensity = intensity_cd;
  l.color = color;
  s.lights.push_back(l);
}

// A standing viewer at eye height looking along -z (glTF's camera convention).
Camera viewer_at(glm::vec3 position_m, float yfov_rad = 1.2f) {
  Camera c;
  c.position_m = position_m;
  c.yfov_rad = yfov_rad;
  return c;
}

// Tiles in linear RGB: light squares with dark grout every `tile` texels.
Texture tile_texture(glm::vec3 tile_rgb, glm::vec3 grout_rgb, uint32_t size, uint32_t tile) {
  Texture t;
  t.width = t.height = size;
  t.texels.resize(std::size_t(size) * size);
  for (uint32_t y = 0; y < size; ++y)
    for (uint32_t x = 0; x < size; ++x) {
      const bool grout = x % tile < 2 || y % tile < 2;
      const float shade = 0.85f + 0.15f * float(((x / tile) * 7 + (y / tile) * 13) % 5) / 4.0f;
      t.texels[std::size_t(y) * size + x] = glm::vec4(grout ? grout_rgb : tile_rgb * shade, 1.0f);
    }
  return t;
}

// The shell of a closed room: floor, ceiling and four walls facing inwards.
void room_shell(Builder& b, glm::vec3 lo, glm::vec3 hi, uint32_t floor, uint32_t ceiling, uint32_t wall,
                uint32_t end_wall) {
  b.quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}, floor, hi.x - lo.x, hi.z - lo.z);
  b.quad({lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}, ceiling);
  b.quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}, end_wall, hi.x - lo.x, hi.y - lo.y);
  b.quad({hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, wall);
  b.quad({lo.x, lo.y, hi.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, wall, hi.z - lo.z, hi.y - lo.y);
  b.quad({hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}, wall, hi.z - lo.z, hi.y - lo.y);
}

}  // namespace

Scene make_lit_room() {
  Scene s;
  s.source = "room";
  s.ambient = glm::vec3(1.5f);  // a rough stand-in for the light the walls bounce, in the lights' units
  Builder b(s);
  const uint32_t floor = b.material(diffuse("oak floor", {0.45f, 0.30f, 0.18f}));
  const uint32_t ceiling = b.material(diffuse("ceiling", {0.8f, 0.8f, 0.8f}));
  const uint32_t wall = b.material(diffuse("plaster", {0.7f, 0.68f, 0.62f}));
  const uint32_t accent = b.material(diffuse("accent wall", {0.2f, 0.35f, 0.55f}));
  const uint32_t wood = b.material(diffuse("table", {0.35f, 0.2f, 0.1f}));
  const uint32_t fabric = b.material(diffuse("sofa", {0.6f, 0.12f, 0.1f}));
  room_shell(b, {-4.0f, 0.0f, -6.0f}, {4.0f, 3.0f, 4.0f}, floor, ceiling, wall, accent);
  for (int i = 0; i < 3; ++i) {  // tables with legs, and a sofa along each side
    const float z = -4.5f + 2.2f * float(i);
    b.box({-1.0f, 0.72f, z - 0.5f}, {1.0f, 0.77f, z + 0.5f}, wood);
    for (float lx : {-0.95f, 0.9f})
      for (float lz : {-0.45f, 0.4f}) b.box({lx, 0.0f, z + lz}, {lx + 0.05f, 0.72f, z + lz + 0.05f}, wood);
  }
  b.box({-3.9f, 0.0f, -5.0f}, {-3.0f, 0.8f, -1.0f}, fabric);
  b.box({3.0f, 0.0f, -5.0f}, {3.9f, 0.8f, -1.0f}, fabric);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) point_light(s, {-2.5f + 2.5f * float(i), 2.7f, -5.0f + 2.6f * float(j)}, 108.0f);
  s.camera = viewer_at({0.0f, 1.6f, 3.0f});
  return s;
}

Scene make_textured_hall() {
  Scene s;
  s.source = "hall";
  s.ambient = glm::vec3(0.8f);
  s.sky_zenith = glm::vec3(6.0f, 7.0f, 9.0f);  // daylight through the open end, in the lights' units
  s.sky_horizon = glm::vec3(9.0f, 9.0f, 9.5f);
  Builder b(s);
  const uint32_t tiles = b.texture(tile_texture({0.7f, 0.68f, 0.6f}, {0.1f, 0.1f, 0.1f}, 128, 32));
  const uint32_t panels = b.texture(tile_texture({0.45f, 0.3f, 0.2f}, {0.15f, 0.1f, 0.06f}, 128, 64));
  Material floor = diffuse("tiled floor", glm::vec3(1.0f), 0.6f);
  floor.base_color_texture = int(tiles);
  Material wall = diffuse("panelled wall", glm::vec3(1.0f));
  wall.base_color_texture = int(panels);
  const uint32_t floor_m = b.material(floor), wall_m = b.material(wall);
  const uint32_t ceiling = b.material(diffuse("vault", {0.75f, 0.72f, 0.68f}));
  const uint32_t stone = b.material(diffuse("column", {0.6f, 0.58f, 0.55f}));
  const float lo_z = -28.0f, hi_z = 2.0f;
  b.quad({-3.0f, 0.0f, hi_z}, {3.0f, 0.0f, hi_z}, {3.0f, 0.0f, lo_z}, {-3.0f, 0.0f, lo_z}, floor_m, 6.0f, hi_z - lo_z);
  b.quad({-3.0f, 5.0f, lo_z}, {3.0f, 5.0f, lo_z}, {3.0f, 5.0f, hi_z}, {-3.0f, 5.0f, hi_z}, ceiling);
  b.quad({-3.0f, 0.0f, hi_z}, {-3.0f, 0.0f, lo_z}, {-3.0f, 5.0f, lo_z}, {-3.0f, 5.0f, hi_z}, wall_m, hi_z - lo_z, 5.0f);
  b.quad({3.0f, 0.0f, lo_z}, {3.0f, 0.0f, hi_z}, {3.0f, 5.0f, hi_z}, {3.0f, 5.0f, lo_z}, wall_m, hi_z - lo_z, 5.0f);
  b.quad({3.0f, 0.0f, hi_z}, {-3.0f, 0.0f, hi_z}, {-3.0f, 5.0f, hi_z}, {3.0f, 5.0f, hi_z}, wall_m, 6.0f, 5.0f);
  for (int i = 0; i < 7; ++i) {  // columns along both walls; the far end stays open
    const float z = -1.0f - 4.0f * float(i);
    b.box({-2.8f, 0.0f, z - 0.3f}, {-2.2f, 5.0f, z + 0.3f}, stone);
    b.box({2.2f, 0.0f, z - 0.3f}, {2.8f, 5.0f, z + 0.3f}, stone);
    Light spot;
    spot.type = LightType::kSpot;
    spot.position = {0.0f, 4.8f, z + 2.0f};
    spot.direction = {0.0f, -1.0f, 0.0f};
    spot.intensity = 400.0f;
    spot.outer_cone_rad = 0.9f;
    spot.inner_cone_rad = 0.5f;
    s.lights.push_back(spot);
  }
  s.camera = viewer_at({0.0f, 1.6f, 0.5f});
  return s;
}

Scene make_dense_room() {
  Scene s;
  s.source = "dense";
  s.ambient = glm::vec3(1.0f);
  Builder b(s);
  const uint32_t floor = b.material(diffuse("floor", {0.5f, 0.5f, 0.5f}));
  const uint32_t wall = b.material(diffuse("wall", {0.65f, 0.65f, 0.6f}));
  const uint32_t colours[3] = {b.material(diffuse("red", {0.7f, 0.15f, 0.1f}, 0.8f)),
                               b.material(diffuse("green", {0.15f, 0.6f, 0.2f}, 0.8f)),
                               b.material(diffuse("blue", {0.1f, 0.2f, 0.7f}, 0.8f))};
  room_shell(b, {-6.0f, 0.0f, -14.0f}, {6.0f, 4.0f, 3.0f}, floor, wall, wall, wall);
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 30; ++j) {
      const float x = -5.0f + 0.5f * float(i) + 0.1f * float(j % 3);
      const float z = -13.0f + 0.5f * float(j);
      const float y = 0.2f + 0.15f * float((i * 7 + j * 3) % 5);
      if (std::abs(x) < 0.6f && z > -3.0f) continue;  // the aisle the viewer stands in
      b.sphere({x, y, z}, 0.2f, colours[(i + j) % 3], 24, 12);
    }
  for (float x : {-3.0f, 3.0f})
    for (float z : {-10.0f, -3.0f}) point_light(s, {x, 3.7f, z}, 150.0f);
  s.camera = viewer_at({0.0f, 1.6f, 1.5f});
  return s;
}

const std::vector<std::string>& procedural_scene_names() {
  static const std::vector<std::string> names = {"room", "hall", "dense"};
  return names;
}

std::optional<Scene> make_procedural_scene(const std::string& name) {
  if (name == "room") return make_lit_room();
  if (name == "hall") return make_textured_hall();
  if (name == "dense") return make_dense_room();
  return std::nullopt;
}

}  // namespace foveart::engine
