// glTF loading: hand-made minimal files in all three container forms, every
// feature the engine reads, broken files with clear errors, Debian's test models.
#include "gltf_fixtures.hpp"

#include <engine/effects.hpp>
#include <engine/gltf_loader.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

using foveart::engine::load_gltf;
using foveart::engine::LoadResult;
using namespace engine_test;

namespace {

void expect_unit_quad(const LoadResult& r) {
  ASSERT_TRUE(r.ok()) << r.error;
  const auto& m = r.scene->mesh;
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[2], glm::vec3(1, 1, 0));
  EXPECT_EQ(m.normals[0], glm::vec3(0, 0, 1));
  ASSERT_EQ(m.uv0.size(), 4u);
  EXPECT_EQ(m.uv0[3], glm::vec2(0, 0));
  ASSERT_EQ(r.scene->textures.size(), 1u);
  const auto& t = r.scene->textures[0];
  ASSERT_EQ(t.width, 2u);
  EXPECT_NEAR(t.texels[0].r, 1.0f, 1e-6f);  // red, top-left
  EXPECT_NEAR(t.texels[0].g, 0.0f, 1e-6f);
  EXPECT_NEAR(t.texels[1].g, 1.0f, 1e-6f);  // green, top-right
  EXPECT_TRUE(t.nearest);
  EXPECT_EQ(r.scene->materials[0].base_color_texture, 0);
  EXPECT_TRUE(foveart::engine::derive_effects(*r.scene).textures);
}

void expect_error(const LoadResult& r, const std::filesystem::path& file, const std::string& phrase) {
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find(file.string()), std::string::npos) << r.error;
  EXPECT_NE(r.error.find(phrase), std::string::npos) << r.error;
}

}  // namespace

TEST(GltfLoader, ExternalBufferFile) {
  TempDir dir;
  expect_unit_quad(load_gltf(write_external(dir.path, "quad", unit_quad(true)).string()));
}

TEST(GltfLoader, EmbeddedDataUriBuffer) {
  TempDir dir;
  expect_unit_quad(load_gltf(write_embedded(dir.path, "quad", unit_quad(true)).string()));
}

TEST(GltfLoader, BinaryGlb) {
  TempDir dir;
  expect_unit_quad(load_gltf(write_glb(dir.path, "quad", unit_quad(true)).string()));
}

TEST(GltfLoader, NodeHierarchyTransformsAreComposed) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  // Parent translates by (10, 0, 0); child scales by 2 and rotates 90 deg about +z.
  const float s = std::sqrt(0.5f);
  doc.json["nodes"] = {{{"translation", {10.0, 0.0, 0.0}}, {"children", {1}}},
                       {{"mesh", 0}, {"scale", {2.0, 2.0, 2.0}}, {"rotation", {0.0, 0.0, s, s}}}};
  const LoadResult r = load_gltf(write_embedded(dir.path, "tree", doc).string());
  ASSERT_TRUE(r.ok()) << r.error;
  const glm::vec3 p = r.scene->mesh.positions[1];  // (1,0,0) -> rotate -> (0,1,0) -> *2 -> +10x
  EXPECT_NEAR(p.x, 10.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  const glm::vec3 n = r.scene->mesh.normals[1];
  EXPECT_NEAR(n.z, 1.0f, 1e-5f);
}

TEST(GltfLoader, LightsTransmissionEmissiveAlphaAndCamera) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.json["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior"};
  doc.json["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "point"}, {"intensity", 5.0}, {"color", {1.0, 0.5, 0.25}}},
      {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}},
      {{"type", "directional"}, {"intensity", 3.0}}};
  doc.json["nodes"].push_back({{"translation", {0.0, 3.0, 0.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  doc.json["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  doc.json["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  doc.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
  doc.json["nodes"].push_back({{"camera", 0}, {"translation", {0.0, 0.0, 5.0}}});
  doc.json["scenes"][0]["nodes"] = {0, 1, 2, 3, 4};
  auto& mat = doc.json["materials"][0];
  mat["emissiveFactor"] = {0.5, 0.25, 0.0};
  mat["alphaMode"] = "MASK";
  mat["alphaCutoff"] = 0.3;
  mat["doubleSided"] = true;
  mat["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}},
                       {"KHR_materials_ior", {{"ior", 1.33}}}};
  const LoadResult r = load_gltf(write_embedded(dir.path, "features", doc).string());
  ASSERT_TRUE(r.ok()) << r.error;
  const auto& s = *r.scene;
  ASSERT_EQ(s.lights.size(), 3u);
  EXPECT_EQ(s.lights[0].type, foveart::engine::LightType::kPoint);
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 5.0f);
  EXPECT_FLOAT_EQ(s.lights[0].position.y, 3.0f);
  EXPECT_FLOAT_EQ(s.lights[0].color.y, 0.5f);
  EXPECT_EQ(s.lights[1].type, foveart::engine::LightType::kSpot);
  EXPECT_FLOAT_EQ(s.lights[1].outer_cone_rad, 0.5f);
  EXPECT_EQ(s.lights[2].type, foveart::engine::LightType::kDirectional);
  EXPECT_NEAR(s.lights[2].direction.z, -1.0f, 1e-6f);
  const auto& m = s.materials[0];
  EXPECT_FLOAT_EQ(m.transmission, 0.8f);
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.emissive.x, 0.5f);
  EXPECT_EQ(m.alpha_mode, foveart::engine::AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_FLOAT_EQ(s.camera->yfov_rad, 0.7f);
  EXPECT_FLOAT_EQ(s.camera->position_m.z, 5.0f);
  const auto fx = foveart::engine::derive_effects(s);
  EXPECT_TRUE(fx.shadows);
  EXPECT_TRUE(fx.refraction);
  EXPECT_FALSE(fx.reflection);  // roughness 1
  EXPECT_FALSE(fx.textures);
}

TEST(GltfLoader, NonIndexedStripAndFanPrimitives) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  auto prim = doc.json["meshes"][0]["primitives"][0];
  prim.erase("indices");
  prim["mode"] = 5;  // strip 0,1,2,3 -> 2 triangles
  auto fan = prim;
  fan["mode"] = 6;   // fan 0,1,2,3 -> 2 triangles
  auto lines = prim;
  lines["mode"] = 1;  // skipped with a warning
  doc.json["meshes"][0]["primitives"] = {prim, fan, lines};
  const LoadResult r = load_gltf(write_embedded(dir.path, "modes", doc).string());
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.scene->mesh.triangles.size(), 4u);
  EXPECT_FALSE(r.scene->warnings.empty());
}

TEST(GltfLoaderErrors, MissingFile) {
  TempDir dir;
  const auto p = dir.path / "nope.gltf";
  expect_error(load_gltf(p.string()), p, "no such file");
}

// A camera whose transform leaves no view (a zero scale, or a place beyond 1e9 m) is ignored with a
// warning: the scene is then framed as one without a camera, never shown through NaN rays.
TEST(GltfLoader, ACameraThatCannotSeeIsIgnoredWithAWarning) {
  for (const nlohmann::json& node : {nlohmann::json{{"camera", 0}, {"scale", {0.0, 0.0, 0.0}}},
                                     nlohmann::json{{"camera", 0}, {"translation", {1e30, 0.0, 0.0}}}}) {
    TempDir dir;
    GltfDoc doc = unit_quad(false);
    doc.json["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
    doc.json["nodes"].push_back(node);
    doc.json["scenes"][0]["nodes"] = {0, 1};
    const LoadResult r = load_gltf(write_embedded(dir.path, "camera", doc).string());
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_FALSE(r.scene->camera.has_value()) << node.dump();
    ASSERT_EQ(r.scene->warnings.size(), 1u) << node.dump();
    EXPECT_EQ(r.scene->warnings[0], "camera 0: its transform has a zero scale or puts it beyond 1e9 m; ignored");
  }
}

TEST(GltfLoaderErrors, ADirectoryOrDeviceIsNotAFile) {
  TempDir dir;
  expect_error(load_gltf(dir.path.string()), dir.path, "a directory, not a file");
  expect_error(load_gltf("/dev/null"), "/dev/null", "not a regular file");
}

TEST(GltfLoaderErrors, MalformedJson) {
  TempDir dir;
  const auto p = write_text(dir.path, "bad.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [");
  expect_error(load_gltf(p.string()), p, "malformed JSON");
}

TEST(GltfLoaderErrors, MissingBin) {
  TempDir dir;
  const auto p = write_external(dir.path, "quad", unit_quad(false));
  std::filesystem::remove(dir.path / "quad.bin");
  expect_error(load_gltf(p.string()), p, "quad.bin");
}

TEST(GltfLoaderErrors, IndexOutOfRange) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.bin[doc.json["bufferViews"][3]["byteOffset"].get<size_t>()] = 9;  // first index -> 9 of 4 vertices
  const auto p = write_embedded(dir.path, "oob", doc);
  expect_error(load_gltf(p.string()), p, "out of range");
}

TEST(GltfLoaderErrors, AccessorPastEndOfBufferView) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][0]["count"] = 400;
  const auto p = write_embedded(dir.path, "short", doc);
  const LoadResult r = load_gltf(p.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find(p.string()), std::string::npos) << r.error;
}

// Accessor counts whose element or byte arithmetic wraps size_t. Before checked arithmetic these
// passed the bounds check (the wrapped byte length was small) and then wrote count elements into a
// vector sized by the wrapped product: heap corruption and SIGSEGV in `fovea render`.
namespace {
void expect_accessor_overflow_rejected(const std::string& name, GltfDoc doc, const std::string& accessor_phrase) {
  TempDir dir;
  const auto p = write_embedded(dir.path, name, std::move(doc));
  const LoadResult r = foveart::engine::load_scene(p.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find(p.string()), std::string::npos) << r.error;
  EXPECT_NE(r.error.find(accessor_phrase), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("overflow"), std::string::npos) << r.error;
}
}  // namespace

TEST(GltfLoaderErrors, PositionCountTimesComponentsWraps) {
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][0]["count"] = 0x5555555555555556ull;  // x 3 components = 2^64 + 2; x 12 bytes wraps too
  expect_accessor_overflow_rejected("pos_wrap", doc, "POSITION: accessor 0");
}

TEST(GltfLoaderErrors, PositionHugeCountByteLengthWraps) {
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][0]["count"] = 0x4000000000000001ull;  // (count - 1) x 12 bytes = 3 x 2^64 -> 0
  expect_accessor_overflow_rejected("pos_huge", doc, "POSITION: accessor 0");
}

TEST(GltfLoaderErrors, TexcoordCountTimesComponentsWraps) {
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][2]["count"] = 0x8000000000000001ull;  // x 2 components = 2^64 + 2
  expect_accessor_overflow_rejected("uv_wrap", doc, "TEXCOORD_0: accessor 2");
}

TEST(GltfLoaderErrors, StrideTimesCountWraps) {
  GltfDoc doc = unit_quad(false);
  doc.json["bufferViews"][0]["byteStride"] = 16;
  doc.json["accessors"][0]["count"] = 0x1000000000000001ull;  // (count - 1) x 16-byte stride = 2^64 -> 0
  expect_accessor_overflow_rejected("stride_wrap", doc, "POSITION: accessor 0");
}

TEST(GltfLoaderErrors, IndexCountTimesBytesWraps) {
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][3]["count"] = 0x8000000000000001ull;  // (count - 1) x 2 bytes = 2^64 -> 0
  expect_accessor_overflow_rejected("idx_wrap", doc, "indices: accessor 3");
}

// An accessor without a bufferView is zeros: legal, and loaded as such.
TEST(GltfLoader, AccessorWithoutBufferViewIsZeros) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.json["accessors"][2].erase("bufferView");  // TEXCOORD_0, 4 elements
  const LoadResult r = load_gltf(write_embedded(dir.path, "uv_zeros", doc).string());
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.scene->mesh.uv0.size(), 4u);
  for (const glm::vec2& uv : r.scene->mesh.uv0) EXPECT_EQ(uv, glm::vec2(0.0f));
}

// fuzz_gltf found this: a TEXCOORD accessor without a bufferView claiming 8.9e16 elements made the
// loader allocate what the count said (ASan: allocator out of memory; without ASan bad_alloc, or at
// a smaller claim an overcommitted zero fill). No byte of the file backs such a count: refused first.
TEST(GltfLoaderErrors, AccessorWithoutBufferViewClaimingMoreElementsThanTheFileHolds) {
  for (const int accessor : {0, 2}) {  // POSITION, TEXCOORD_0 (tinygltf refuses indices without a bufferView)
    SCOPED_TRACE(accessor);
    TempDir dir;
    GltfDoc doc = unit_quad(false);
    doc.json["accessors"][accessor].erase("bufferView");
    doc.json["accessors"][accessor]["count"] = 1ull << 40;  // 4-16 TB as floats; no size_t arithmetic wraps
    const auto p = write_embedded(dir.path, "zeros_claim", doc);
    const LoadResult r = load_gltf(p.string());
    expect_error(r, p, "accessor " + std::to_string(accessor) + " has no bufferView and claims 1099511627776 elements");
  }
}

TEST(GltfLoaderErrors, UnsupportedRequiredExtension) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.json["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  doc.json["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  const auto p = write_embedded(dir.path, "draco", doc);
  expect_error(load_gltf(p.string()), p, "unsupported required extension KHR_draco_mesh_compression");
}

TEST(GltfLoaderErrors, CyclicNodeHierarchy) {
  TempDir dir;
  GltfDoc doc = unit_quad(false);
  doc.json["nodes"] = {{{"mesh", 0}, {"children", {1}}}, {{"children", {0}}}};
  const auto p = write_embedded(dir.path, "cycle", doc);
  expect_error(load_gltf(p.string()), p, "cyclic");
}

// A mesh that no node instances is still part of the file: a missing accessor or material
// in it makes the file malformed, not an empty scene with a warning.
TEST(GltfLoaderErrors, UninstancedMeshWithMissingReferences) {
  const std::vector<std::pair<std::string, std::string>> breakages = {
      {"attribute", "mesh 1 ('spare') primitive 0 POSITION: accessor 42 does not exist"},
      {"indices", "indices accessor out of bounds"},  // tinygltf's own check
      {"material", "mesh 1 ('spare') primitive 0: material 44 does not exist"}};
  for (const auto& [part, phrase] : breakages) {
    SCOPED_TRACE(part);
    TempDir dir;
    GltfDoc doc = unit_quad(false);
    nlohmann::json spare = doc.json["meshes"][0];
    spare["name"] = "spare";
    nlohmann::json& prim = spare["primitives"][0];
    if (part == "attribute") prim["attributes"]["POSITION"] = 42;
    if (part == "indices") prim["indices"] = 43;
    if (part == "material") prim["material"] = 44;
    doc.json["meshes"].push_back(spare);
    const auto p = write_embedded(dir.path, "spare_" + part, doc);
    expect_error(load_gltf(p.string()), p, phrase);
  }
}

TEST(GltfLoaderErrors, TruncatedGlb) {
  TempDir dir;
  const auto p = write_glb(dir.path, "quad", unit_quad(false));
  std::filesystem::resize_file(p, 30);
  const LoadResult r = load_gltf(p.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find(p.string()), std::string::npos) << r.error;
}

TEST(GltfLoaderErrors, GlbWithoutItsMagicSaysSo) {
  TempDir dir;
  const auto p = write_glb(dir.path, "quad", unit_quad(false));
  {
    std::fstream f(p, std::ios::binary | std::ios::in | std::ios::out);
    f.write("JUNK", 4);
  }
  expect_error(load_gltf(p.string()), p, "not a binary glTF");
}

// Debian's assimp-testmodels: the valid glTF 2.0 files load; the deliberately
// broken ones fail with an error that names the file and the problem.
TEST(AssimpTestModels, ValidFilesLoadAndBrokenFilesFailClearly) {
  const std::filesystem::path root = FOVEART_ASSIMP_GLTF2_DIR;
  ASSERT_TRUE(std::filesystem::is_directory(root)) << root << ": assimp-testmodels (installed by scripts/setup.sh) is missing";
  const std::vector<std::pair<std::string, std::string>> broken = {
      {"IndexOutOfRange/IndexOutOfRange.gltf", "out of range"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "out of range"},
      {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
      {"RecursiveNodes/RecursiveNodes.gltf", "cyclic"},
      {"draco/2CylinderEngine.gltf", "KHR_draco_mesh_compression"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "non-finite"},
      {"wrongTypes/badArray.gltf", "not an array"},
      {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", "unsupported required extension"}};
  const std::vector<std::string> valid = {
      "BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
      "BoxTextured-glTF-Embedded/BoxTextured.gltf", "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
      "cameras/Cameras.gltf", "TestNoRootNode/NoScene.gltf", "simple_skin/simple_skin.gltf"};
  for (const auto& [file, phrase] : broken) {
    const auto p = root / file;
    if (!std::filesystem::exists(p)) continue;
    SCOPED_TRACE(file);
    expect_error(load_gltf(p.string()), p, phrase);
  }
  int loaded = 0;
  for (const std::string& file : valid) {
    const auto p = root / file;
    if (!std::filesystem::exists(p)) continue;
    const LoadResult r = load_gltf(p.string());
    EXPECT_TRUE(r.ok()) << r.error;
    ++loaded;
  }
  EXPECT_GT(loaded, 0);
  // Everything else: either loads or fails with the file's name in the message; never crashes.
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    const auto ext = entry.path().extension();
    if (ext != ".gltf" && ext != ".glb") continue;
    const LoadResult r = load_gltf(entry.path().string());
    if (!r.ok()) {
      EXPECT_NE(r.error.find(entry.path().string()), std::string::npos) << r.error;
    }
  }
}
