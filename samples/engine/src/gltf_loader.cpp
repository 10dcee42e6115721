// glTF 2.0 -> engine Scene. Every read from a buffer is bounds-checked: a
// broken file produces "<file>: <problem>", never a crash.
#include <engine/gltf_loader.hpp>

#include <engine/default_scene.hpp>
#include <engine/procedural_scenes.hpp>
#include <foveation/eye_view_check.hpp>
#include <foveation/input_file.hpp>

#include "gltf_accessors.hpp"
#include "srgb.hpp"

#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>

namespace foveart::engine {
namespace {

using gltf::BadInput;
using gltf::checked_mul;

// Extensions the engine understands; any other *required* one is an error.
const std::set<std::string> kSupportedExtensions = {
    "KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
    "KHR_materials_emissive_strength", "KHR_materials_pbrSpecularGlossiness"};

constexpr int kMaxNodeDepth = 256;

double number_or(const tinygltf::Value& obj, const char* key, double fallback) {
  if (!obj.IsObject() || !obj.Has(key)) return fallback;
  const tinygltf::Value& v = obj.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

const tinygltf::Value* find_extension(const tinygltf::ExtensionMap& ext, const char* name) {
  auto it = ext.find(name);
  return it == ext.end() ? nullptr : &it->second;
}

// The triangles of a primitive's indices in its mode (triangles, strip or fan).
std::vector<glm::uvec3> triangles_of(int mode, const std::vector<uint32_t>& idx) {
  std::vector<glm::uvec3> tris;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < idx.size(); i += 3) tris.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < idx.size(); ++i)
      tris.push_back(i % 2 == 0 ? glm::uvec3(idx[i], idx[i + 1], idx[i + 2])
                                : glm::uvec3(idx[i + 1], idx[i], idx[i + 2]));
  } else {
    for (size_t i = 1; i + 1 < idx.size(); ++i) tris.emplace_back(idx[0], idx[i], idx[i + 1]);
  }
  return tris;
}

class Loader {
 public:
  Loader(const tinygltf::Model& model, Scene& scene) : model_(model), scene_(scene), accessors_(model) {}

  void run() {
    check_required_extensions();
    check_mesh_references();
    load_textures();
    load_materials();
    const std::vector<int> roots = root_nodes();
    std::vector<bool> on_path(model_.nodes.size(), false);
    for (int node : roots) visit_node(node, glm::mat4(1.0f), on_path, 0);
    if (scene_.mesh.triangles.empty()) scene_.warnings.push_back("no triangles: nothing to ray trace");
  }

 private:
  void check_required_extensions() {
    for (const std::string& ext : model_.extensionsRequired) {
      if (!kSupportedExtensions.count(ext))
        throw BadInput("unsupported required extension " + ext);
    }
    for (const std::string& ext : model_.extensionsUsed) {
      if (!kSupportedExtensions.count(ext)) scene_.warnings.push_back("ignored extension " + ext);
    }
  }

  // Every mesh's attribute accessors and material must exist, whether or not a node of the
  // scene instances it: a file that names a missing object is malformed (glTF 2.0, 3.7),
  // and it is refused rather than rendered with the broken part silently left out.
  // (tinygltf itself refuses a primitive's missing index accessor.)
  void check_mesh_references() const {
    const auto exists = [](int index, size_t count) { return index >= 0 && static_cast<size_t>(index) < count; };
    for (size_t m = 0; m < model_.meshes.size(); ++m) {
      const tinygltf::Mesh& mesh = model_.meshes[m];
      for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = mesh.primitives[p];
        const std::string what = "mesh " + std::to_string(m) + " ('" + mesh.name + "') primitive " + std::to_string(p);
        for (const auto& [semantic, accessor] : prim.attributes)
          if (!exists(accessor, model_.accessors.size()))
            throw BadInput(what + " " + semantic + ": accessor " + std::to_string(accessor) + " does not exist");
        if (prim.material >= 0 && !exists(prim.material, model_.materials.size()))
          throw BadInput(what + ": material " + std::to_string(prim.material) + " does not exist");
      }
    }
  }

  // -- Textures and materials -----------------------------------------------------------
  void load_textures() {
    texture_map_.assign(model_.textures.size(), -1);
    for (size_t i = 0; i < model_.textures.size(); ++i) {
      const tinygltf::Texture& t = model_.textures[i];
      int source = t.source;
      if (source < 0) {  // e.g. only in an unsupported extension (KHR_texture_basisu)
        scene_.warnings.push_back("texture " + std::to_string(i) + " has no usable image");
        continue;
      }
      if (static_cast<size_t>(source) >= model_.images.size())
        throw BadInput("texture " + std::to_string(i) + " refers to missing image " +
                       std::to_string(source));
      const tinygltf::Image& img = model_.images[source];
      const int comp = img.component;
      const int bytes = img.bits == 16 ? 2 : 1;
      const std::string where = "image " + std::to_string(source) + " (" + img.uri + ")";
      if (img.width <= 0 || img.height <= 0 || comp < 1 || comp > 4 || (img.bits != 8 && img.bits != 16) ||
          img.image.size() < checked_mul(checked_mul(static_cast<size_t>(img.width), static_cast<size_t>(img.height),
                                                     where + " width x height"),
                                         static_cast<size_t>(comp * bytes), where + " texels x bytes")) {
        scene_.warnings.push_back(where + " could not be decoded; texture ignored");
        continue;
      }
      Texture tex;
      tex.width = static_cast<uint32_t>(img.width);
      tex.height = static_cast<uint32_t>(img.height);
      tex.texels.resize(static_cast<size_t>(tex.width) * tex.height);
      for (size_t p = 0; p < tex.texels.size(); ++p) {
        float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int k = 0; k < comp; ++k) {
          const size_t at = (p * comp + k) * bytes;
          const float v = bytes == 2 ? static_cast<float>(img.image[at] | (img.image[at + 1] << 8)) / 65535.0f
                                     : static_cast<float>(img.image[at]) / 255.0f;
          c[k] = v;
        }
        if (comp <= 2) {  // grey (+ alpha)
          c[3] = comp == 2 ? c[1] : 1.0f;
          c[1] = c[2] = c[0];
        }
        tex.texels[p] = glm::vec4(srgb_to_linear(c[0]), srgb_to_linear(c[1]), srgb_to_linear(c[2]), c[3]);
      }
      if (t.sampler >= 0 && static_cast<size_t>(t.sampler) < model_.samplers.size()) {
        const tinygltf::Sampler& s = model_.samplers[t.sampler];
        tex.wrap_s = wrap(s.wrapS);
        tex.wrap_t = wrap(s.wrapT);
        tex.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
      }
      texture_map_[i] = static_cast<int>(scene_.textures.size());
      scene_.textures.push_back(std::move(tex));
    }
  }

  static WrapMode wrap(int w) {
    if (w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE) return WrapMode::kClamp;
    if (w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT) return WrapMode::kMirror;
    return WrapMode::kRepeat;
  }

  int texture_index(int gltf_index) const {
    if (gltf_index < 0) return -1;
    if (static_cast<size_t>(gltf_index) >= texture_map_.size())
      throw BadInput("material refers to missing texture " + std::to_string(gltf_index));
    return texture_map_[gltf_index];
  }

  void load_materials() {
    for (const tinygltf::Material& m : model_.materials) {
      Material out;
      out.name = m.name;
      const auto& pbr = m.pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        out.base_color = glm::vec4(pbr.baseColorFactor[0], pbr.baseColorFactor[1],
                                   pbr.baseColorFactor[2], pbr.baseColorFactor[3]);
      out.base_color_texture = texture_index(pbr.baseColorTexture.index);
      out.base_color_texcoord = pbr.baseColorTexture.texCoord;
      out.metallic = static_cast<float>(std::clamp(pbr.metallicFactor, 0.0, 1.0));
      out.roughness = static_cast<float>(std::clamp(pbr.roughnessFactor, 0.0, 1.0));
      if (m.emissiveFactor.size() == 3)
        out.emissive = glm::vec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
      if (const tinygltf::Value* e = find_extension(m.extensions, "KHR_materials_emissive_strength"))
        out.emissive *= static_cast<float>(number_or(*e, "emissiveStrength", 1.0));
      if (m.alphaMode == "MASK") out.alpha_mode = AlphaMode::kMask;
      else if (m.alphaMode == "BLEND") out.alpha_mode = AlphaMode::kBlend;
      out.alpha_cutoff = static_cast<float>(m.alphaCutoff);
      out.double_sided = m.doubleSided;
      if (const tinygltf::Value* e = find_extension(m.extensions, "KHR_materials_transmission"))
        out.transmission = static_cast<float>(std::clamp(number_or(*e, "transmissionFactor", 0.0), 0.0, 1.0));
      if (const tinygltf::Value* e = find_extension(m.extensions, "KHR_materials_ior"))
        out.ior = static_cast<float>(std::max(number_or(*e, "ior", 1.5), 1.0));
      if (const tinygltf::Value* e = find_extension(m.extensions, "KHR_materials_pbrSpecularGlossiness")) {
        // Approximate: diffuse as base colour, glossiness as smoothness, no metal.
        if (e->IsObject() && e->Has("diffuseFactor") && e->Get("diffuseFactor").IsArray() &&
            e->Get("diffuseFactor").ArrayLen() == 4)
          for (int k = 0; k < 4; ++k)
            out.base_color[k] = static_cast<float>(e->Get("diffuseFactor").Get(k).GetNumberAsDouble());
        if (e->IsObject() && e->Has("diffuseTexture") && e->Get("diffuseTexture").IsObject())
          out.base_color_texture =
              texture_index(static_cast<int>(number_or(e->Get("diffuseTexture"), "index", -1.0)));
        out.metallic = 0.0f;
        out.roughness = 1.0f - static_cast<float>(std::clamp(number_or(*e, "glossinessFactor", 1.0), 0.0, 1.0));
      }
      if (out.base_color_texcoord < 0 || out.base_color_texcoord > 1) {
        scene_.warnings.push_back("material '" + m.name + "' uses TEXCOORD_" +
                                  std::to_string(out.base_color_texcoord) + "; only 0 and 1 are read");
        out.base_color_texture = -1;
      }
      scene_.materials.push_back(std::move(out));
    }
  }

  uint32_t default_material() {
    if (default_material_ < 0) {
      default_material_ = static_cast<int>(scene_.materials.size());
      Material m;
      m.name = "(default)";
      scene_.materials.push_back(m);
    }
    return static_cast<uint32_t>(default_material_);
  }

  // -- Node hierarchy ------------------------------------------------------------------
  std::vector<int> root_nodes() const {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      int s = model_.defaultScene;
      if (s < 0) s = 0;
      if (static_cast<size_t>(s) >= model_.scenes.size())
        throw BadInput("default scene " + std::to_string(s) + " does not exist");
      roots = model_.scenes[s].nodes;
    } else {  // no scene: every node that is nobody's child
      std::vector<bool> child(model_.nodes.size(), false);
      for (const tinygltf::Node& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && static_cast<size_t>(c) < child.size()) child[c] = true;
      for (size_t i = 0; i < child.size(); ++i)
        if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    return roots;
  }

  static glm::mat4 local_matrix(const tinygltf::Node& n) {
    if (n.matrix.size() == 16) {
      glm::mat4 m;
      for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = static_cast<float>(n.matrix[i]);  // column-major
      return m;
    }
    glm::mat4 m(1.0f);
    if (n.translation.size() == 3)
      m = glm::translate(m, glm::vec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4)
      m *= glm::mat4_cast(glm::normalize(glm::quat(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                                                   static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2]))));
    if (n.scale.size() == 3) m = glm::scale(m, glm::vec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
  }

  void visit_node(int index, const glm::mat4& parent, std::vector<bool>& on_path, int depth) {
    if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
      throw BadInput("node " + std::to_string(index) + " does not exist");
    if (on_path[index] || depth > kMaxNodeDepth)
      throw BadInput("node " + std::to_string(index) + " is its own ancestor (cyclic hierarchy)");
    on_path[index] = true;
    const tinygltf::Node& n = model_.nodes[index];
    const glm::mat4 world = parent * local_matrix(n);
    if (n.mesh >= 0) add_mesh(n.mesh, world);
    if (n.camera >= 0) add_camera(n.camera, world);
    if (const tinygltf::Value* e = find_extension(n.extensions, "KHR_lights_punctual"))
      add_light(static_cast<int>(number_or(*e, "light", -1.0)), world);
    for (int c : n.children) visit_node(c, world, on_path, depth + 1);
    on_path[index] = false;
  }

  void add_camera(int index, const glm::mat4& world) {
    if (scene_.camera || index < 0 || static_cast<size_t>(index) >= model_.cameras.size()) return;
    const tinygltf::Camera& c = model_.cameras[index];
    Camera cam;
    cam.position_m = glm::vec3(world[3]);
    const glm::mat3 r(glm::normalize(glm::vec3(world[0])), glm::normalize(glm::vec3(world[1])),
                      glm::normalize(glm::vec3(world[2])));
    cam.orientation = glm::normalize(glm::quat_cast(r));
    const glm::quat& q = cam.orientation;
    if (!foveation::traceable_position(cam.position_m) || !std::isfinite(q.x + q.y + q.z + q.w)) {
      // A zero scale leaves no rotation; a camera past kMaxPositionM sees nothing that can be traced.
      scene_.warnings.push_back("camera " + std::to_string(index) +
                                ": its transform has a zero scale or puts it beyond 1e9 m; ignored");
      return;
    }
    if (c.type == "perspective" && c.perspective.yfov > 0.0) {
      cam.yfov_rad = static_cast<float>(c.perspective.yfov);
      cam.aspect = static_cast<float>(c.perspective.aspectRatio);
    } else {
      scene_.warnings.push_back("camera " + std::to_string(index) + " is not perspective; using its pose only");
    }
    scene_.camera = cam;
  }

  void add_light(int index, const glm::mat4& world) {
    if (index < 0 || static_cast<size_t>(index) >= model_.lights.size())
      throw BadInput("node refers to missing light " + std::to_string(index));
    const tinygltf::Light& l = model_.lights[index];
    Light out;
    if (l.type == "directional") out.type = LightType::kDirectional;
    else if (l.type == "spot") out.type = LightType::kSpot;
    else if (l.type == "point") out.type = LightType::kPoint;
    else throw BadInput("light " + std::to_string(index) + " has unknown type '" + l.type + "'");
    if (l.color.size() == 3) out.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
    out.intensity = static_cast<float>(l.intensity);
    out.range = static_cast<float>(l.range);
    out.inner_cone_rad = static_cast<float>(l.spot.innerConeAngle);
    out.outer_cone_rad = static_cast<float>(l.spot.outerConeAngle);
    out.position = glm::vec3(world[3]);
    out.direction = glm::normalize(glm::vec3(world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    scene_.lights.push_back(out);
  }

  void add_mesh(int index, const glm::mat4& world) {
    if (static_cast<size_t>(index) >= model_.meshes.size())
      throw BadInput("node refers to missing mesh " + std::to_string(index));
    const tinygltf::Mesh& mesh = model_.meshes[index];
    for (size_t p = 0; p < mesh.primitives.size(); ++p)
      add_primitive(mesh.primitives[p],
                    "mesh " + std::to_string(index) + " ('" + mesh.name + "') primitive " + std::to_string(p),
                    world);
  }

  void add_primitive(const tinygltf::Primitive& prim, const std::string& what, const glm::mat4& world) {
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      scene_.warnings.push_back(what + ": points/lines are not ray traced; skipped");
      return;
    }
    if (prim.attributes.find("POSITION") == prim.attributes.end()) {
      scene_.warnings.push_back(what + ": no POSITION; skipped");
      return;
    }
    const VertexData vertices = read_vertices(prim, what);
    const std::vector<glm::uvec3> tris = triangles_of(mode, read_indices(prim, what, vertices.count));
    // prim.material was checked against the materials by check_mesh_references().
    const uint32_t material = prim.material >= 0 ? static_cast<uint32_t>(prim.material) : default_material();
    const size_t first = scene_.mesh.positions.size();
    if (first + vertices.count > 0xFFFFFFFFu) throw BadInput(what + ": too many vertices");
    append_vertices(vertices, world);
    append_triangles(tris, first, glm::determinant(glm::mat3(world)) < 0.0f, material);
  }

  // A primitive's vertex attributes, checked: POSITION (there), NORMAL and TEXCOORD_0/1 if present.
  struct VertexData {
    std::vector<float> pos, nrm, uv[2];
    size_t count = 0;
  };

  VertexData read_vertices(const tinygltf::Primitive& prim, const std::string& what) {
    VertexData d;
    int ncomp = 0;
    d.pos = accessors_.floats(prim.attributes.at("POSITION"), what + " POSITION", &ncomp);
    if (ncomp != 3) throw BadInput(what + ": POSITION must be VEC3");
    d.count = d.pos.size() / 3;
    if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
      d.nrm = accessors_.floats(it->second, what + " NORMAL", &ncomp);
      if (ncomp != 3 || d.nrm.size() != d.pos.size())
        throw BadInput(what + ": NORMAL must be VEC3 with one entry per vertex");
    }
    for (int set = 0; set < 2; ++set) {
      if (auto it = prim.attributes.find("TEXCOORD_" + std::to_string(set)); it != prim.attributes.end()) {
        d.uv[set] = accessors_.floats(it->second, what + " TEXCOORD_" + std::to_string(set), &ncomp);
        if (ncomp != 2 || d.uv[set].size() != d.count * 2)
          throw BadInput(what + ": TEXCOORD_" + std::to_string(set) + " must be VEC2 with one entry per vertex");
      }
    }
    return d;
  }

  // The primitive's indices, each checked against its nvert vertices; without indices, 0 .. nvert - 1.
  std::vector<uint32_t> read_indices(const tinygltf::Primitive& prim, const std::string& what, size_t nvert) {
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
      idx = accessors_.indices(prim.indices, what + " indices");
      for (size_t i = 0; i < idx.size(); ++i)
        if (idx[i] >= nvert)
          throw BadInput(what + ": index " + std::to_string(idx[i]) + " at position " + std::to_string(i) +
                         " is out of range (" + std::to_string(nvert) + " vertices)");
    } else {
      idx.resize(nvert);
      for (size_t i = 0; i < nvert; ++i) idx[i] = static_cast<uint32_t>(i);
    }
    return idx;
  }

  // The vertices into the mesh, in the scene's space: unit normals (0 if none
  // or degenerate), and both UV sets kept as long as the positions once either exists.
  void append_vertices(const VertexData& d, const glm::mat4& world) {
    Mesh& m = scene_.mesh;
    const size_t first = m.positions.size();
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
    for (size_t v = 0; v < d.count; ++v) {
      m.positions.push_back(glm::vec3(world * glm::vec4(d.pos[3 * v], d.pos[3 * v + 1], d.pos[3 * v + 2], 1.0f)));
      glm::vec3 n(0.0f);
      if (!d.nrm.empty()) {
        n = normal_matrix * glm::vec3(d.nrm[3 * v], d.nrm[3 * v + 1], d.nrm[3 * v + 2]);
        const float len = glm::length(n);
        n = len > 1e-12f && std::isfinite(len) ? n / len : glm::vec3(0.0f);
      }
      m.normals.push_back(n);
    }
    for (int set = 0; set < 2; ++set) {
      std::vector<glm::vec2>& dst = set == 0 ? m.uv0 : m.uv1;
      if (d.uv[set].empty() && dst.empty()) continue;
      dst.resize(first, glm::vec2(0.0f));  // earlier primitives without this set
      for (size_t v = 0; v < d.count; ++v)
        dst.push_back(d.uv[set].empty() ? glm::vec2(0.0f) : glm::vec2(d.uv[set][2 * v], d.uv[set][2 * v + 1]));
    }
  }

  // The triangles of vertices from `first` on into the mesh (wound back if the
  // transform mirrors), but for the degenerate ones, which are counted.
  void append_triangles(const std::vector<glm::uvec3>& tris, size_t first, bool flip, uint32_t material) {
    Mesh& m = scene_.mesh;
    size_t degenerate = 0;
    for (const glm::uvec3& t : tris) {
      const glm::uvec3 g = glm::uvec3(static_cast<uint32_t>(first)) + (flip ? glm::uvec3(t.x, t.z, t.y) : t);
      const glm::dvec3 c = glm::cross(glm::dvec3(m.positions[g.y] - m.positions[g.x]),
                                      glm::dvec3(m.positions[g.z] - m.positions[g.x]));
      if (g.x == g.y || g.y == g.z || g.x == g.z || !(glm::dot(c, c) > 0.0)) {
        ++degenerate;
        continue;
      }
      m.triangles.push_back(g);
      m.triangle_material.push_back(material);
    }
    degenerate_ += degenerate;
  }

  const tinygltf::Model& model_;
  Scene& scene_;
  gltf::AccessorReader accessors_;
  std::vector<int> texture_map_;
  int default_material_ = -1;

 public:
  size_t degenerate_ = 0;  // zero-area triangles skipped (reported once)
};

// The JSON part of a .gltf or .glb file, or an error.
std::string read_json_text(const std::string& path, bool* out_glb, std::string* out_json) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) return "cannot open file";
  const std::streamoff size = f.tellg();
  if (size < 0) return "cannot read file";
  std::string bytes(static_cast<size_t>(size), '\0');
  f.seekg(0);
  if (!f.read(bytes.data(), size)) return "cannot read file";
  *out_glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (!*out_glb && ext == ".glb") return "not a binary glTF: the file does not start with 'glTF'";
  if (!*out_glb) {
    *out_json = std::move(bytes);
    return "";
  }
  // GLB: 12-byte header, then chunk 0 (length, type 'JSON', data).
  uint32_t header[5] = {};
  if (bytes.size() < sizeof(header)) return "truncated GLB header";
  std::memcpy(header, bytes.data(), sizeof(header));
  if (header[1] != 2) return "GLB version " + std::to_string(header[1]) + " is not 2";
  if (header[4] != 0x4E4F534Au) return "GLB first chunk is not JSON";
  if (header[3] > bytes.size() - sizeof(header)) return "GLB JSON chunk is longer than the file";
  *out_json = bytes.substr(sizeof(header), header[3]);
  return "";
}

// Checks tinygltf does not make (or words poorly): malformed JSON with its
// position, unsupported required extensions (e.g. Draco) and mesh primitives
// that are not an array.
std::string precheck(const std::string& path, bool* out_glb) {
  std::string text;
  if (std::string e = read_json_text(path, out_glb, &text); !e.empty()) return e;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    return "malformed JSON (at byte " + std::to_string(e.byte) + ")";
  }
  if (!j.is_object()) return "top level JSON value is not an object";
  if (auto it = j.find("extensionsRequired"); it != j.end() && it->is_array())
    for (const auto& ext : *it)
      if (ext.is_string() && !kSupportedExtensions.count(ext.get<std::string>()))
        return "unsupported required extension " + ext.get<std::string>();
  if (auto it = j.find("meshes"); it != j.end() && it->is_array())
    for (size_t i = 0; i < it->size(); ++i) {
      const auto& mesh = (*it)[i];
      if (mesh.is_object() && mesh.contains("primitives") && !mesh["primitives"].is_array())
        return "meshes[" + std::to_string(i) + "].primitives is not an array";
    }
  return "";
}

std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ';');
  return s;
}

}  // namespace

LoadResult load_gltf(const std::string& path) {
  LoadResult result;
  try {
    std::error_code ec;
    std::string problem = foveation::input_file_problem(path);
    if (problem.empty() && !std::filesystem::is_regular_file(path, ec)) problem = "not a regular file";
    if (!problem.empty()) {  // tinygltf reads a file by its size: no pipe or device
      result.error = path + ": " + problem;
      return result;
    }
    bool glb = false;
    if (std::string bad = precheck(path, &glb); !bad.empty()) {
      result.error = path + ": " + bad;
      return result;
    }
    tinygltf::Model model;
    tinygltf::TinyGLTF gltf;
    std::string err, warn;
    const bool ok = glb ? gltf.LoadBinaryFromFile(&model, &err, &warn, path)
                                 : gltf.LoadASCIIFromFile(&model, &err, &warn, path);
    if (!ok) {
      result.error = path + ": " + (err.empty() ? std::string("not a valid glTF 2.0 file") : one_line(err));
      return result;
    }
    Scene scene;
    scene.source = path;
    if (!warn.empty()) scene.warnings.push_back(one_line(warn));
    // Fill unused uv arrays consistently: a set present in a later primitive pads earlier ones.
    Loader loader(model, scene);
    loader.run();
    if (loader.degenerate_ > 0)
      scene.warnings.push_back(std::to_string(loader.degenerate_) + " zero-area triangles skipped");
    Mesh& m = scene.mesh;
    if (!m.uv0.empty()) m.uv0.resize(m.positions.size(), glm::vec2(0.0f));
    if (!m.uv1.empty()) m.uv1.resize(m.positions.size(), glm::vec2(0.0f));
    result.scene = std::move(scene);
  } catch (const BadInput& e) {
    result.error = path + ": " + e.what();
  } catch (const std::bad_alloc&) {
    result.error = path + ": out of memory while loading";
  } catch (const std::exception& e) {
    result.error = path + ": " + e.what();
  }
  return result;
}

LoadResult load_scene(const std::string& spec) {
  if (spec.empty() || spec == "default") {
    LoadResult r;
    r.scene = make_default_scene();
    return r;
  }
  if (std::optional<Scene> procedural = make_procedural_scene(spec)) {
    LoadResult r;
    r.scene = std::move(*procedural);
    return r;
  }
  std::error_code ec;
  if (!std::filesystem::exists(spec, ec) && std::filesystem::path(spec).extension().empty()) {
    LoadResult r;  // neither a file nor a built-in name: most likely a mistyped name
    r.error = spec + ": no such file, and not a built-in scene (default";
    for (const std::string& name : procedural_scene_names()) r.error += ", " + name;
    r.error += ")";
    return r;
  }
  return load_gltf(spec);
}

}  // namespace foveart::engine
