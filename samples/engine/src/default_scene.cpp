// The built-in default scene (see default_scene.hpp), built from quads, boxes
// and a UV sphere. Units are metres; +y up; the viewer stands at z = +3 and
// looks down -z along a hall whose far wall glows.
#include <engine/default_scene.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>

namespace foveart::engine {
namespace {

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

  const uint32_t m_floor = b.material(floor);
  const uint32_t m_wall = b.material(wall);
  const uint32_t m_ceiling = b.material(ceiling);
  const uint32_t m_glow = b.material(glow);
  const uint32_t m_panel = b.material(panel);
  const uint32_t m_pillar = b.material(pillar);
  const uint32_t m_glass = b.material(glass);
  const uint32_t m_crate = b.material(crate);

  const float x0 = -5.0f, x1 = 5.0f, z0 = -18.0f, z1 = 5.0f, h = 4.0f;
  b.quad({x0, 0, z1}, {x1, 0, z1}, {x1, 0, z0}, {x0, 0, z0}, m_floor, 10.0f, 23.0f);       // floor, 1 m checks
  b.quad({x0, h, z0}, {x1, h, z0}, {x1, h, z1}, {x0, h, z1}, m_ceiling);                    // ceiling
  b.quad({x0, 0, z1}, {x0, 0, z0}, {x0, h, z0}, {x0, h, z1}, m_wall, 23.0f, 4.0f);          // left wall
  b.quad({x1, 0, z0}, {x1, 0, z1}, {x1, h, z1}, {x1, h, z0}, m_wall, 23.0f, 4.0f);          // right wall
  b.quad({x0 + 0.5f, 0.0f, z0}, {x1 - 0.5f, 0.0f, z0}, {x1 - 0.5f, h - 0.5f, z0}, {x0 + 0.5f, h - 0.5f, z0},
         m_glow);  // bright far wall; the gap around it shows the bright sky
  b.quad({x1, 0, z1}, {x0, 0, z1}, {x0, h, z1}, {x1, h, z1}, m_wall, 10.0f, 4.0f);          // wall behind the viewer

  for (int i = 0; i < 6; ++i) {  // two rows of dark pillars against the bright wall
    const float z = -2.0f - 2.6f * static_cast<float>(i);
    b.box({-2.6f, 0.0f, z - 0.2f}, {-2.2f, h, z + 0.2f}, m_pillar);
    b.box({2.2f, 0.0f, z - 0.2f}, {2.6f, h, z + 0.2f}, m_pillar);
  }
  // The cross colonnade the view centre looks through: two dark pillars either
  // side of the centre line, 0.4 m apart, seen against the glowing far wall.
  b.box({-0.6f, 0.0f, kColonnadeZ - 0.2f}, {-0.2f, h, kColonnadeZ + 0.2f}, m_pillar);
  b.box({0.2f, 0.0f, kColonnadeZ - 0.2f}, {0.6f, h, kColonnadeZ + 0.2f}, m_pillar);
  for (int i = 0; i < 4; ++i) {  // bright ceiling light panels, each with a point light below
    const float z = -1.0f - 4.0f * static_cast<float>(i);
    b.quad({-0.8f, h - 0.01f, z - 0.4f}, {0.8f, h - 0.01f, z - 0.4f}, {0.8f, h - 0.01f, z + 0.4f},
           {-0.8f, h - 0.01f, z + 0.4f}, m_panel);
    Light l;
    l.type = LightType::kPoint;
    l.position = glm::vec3(0.0f, h - 0.3f, z);
    l.color = glm::vec3(1.0f, 0.96f, 0.9f);
    l.intensity = 14.0f;
    s.lights.push_back(l);
  }
  const DefaultSceneLandmarks marks = default_scene_landmarks();
  b.sphere(marks.glass_centre, kGlassRadius, m_glass);  // far left of the view, between the left pillars and the wall
  b.box({0.9f, 0.0f, -2.2f}, {1.7f, 0.8f, -1.4f}, m_crate, 2.0f);

  Camera cam;
  cam.position_m = glm::vec3(0.0f, 1.6f, 3.0f);
  cam.yfov_rad = 1.6f;
  s.camera = cam;
  return s;
}

}  // namespace foveart::engine
