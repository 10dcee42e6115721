#include "gltf_fixtures.hpp"

#include <stb_image_write.h>

#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>

namespace engine_test {
namespace {

template <typename T>
void append(std::vector<uint8_t>& out, const std::vector<T>& values) {
  const size_t at = out.size();
  out.resize(at + values.size() * sizeof(T));
  std::memcpy(out.data() + at, values.data(), values.size() * sizeof(T));
}

std::string base64(const std::vector<uint8_t>& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = (uint32_t(in[i]) << 16) | (uint32_t(in[i + 1]) << 8) | in[i + 2];
    out += k[(v >> 18) & 63]; out += k[(v >> 12) & 63]; out += k[(v >> 6) & 63]; out += k[v & 63];
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(in[i]) << 16;
    out += k[(v >> 18) & 63]; out += k[(v >> 12) & 63]; out += "==";
  } else if (i + 2 == in.size()) {
    const uint32_t v = (uint32_t(in[i]) << 16) | (uint32_t(in[i + 1]) << 8);
    out += k[(v >> 18) & 63]; out += k[(v >> 12) & 63]; out += k[(v >> 6) & 63]; out += '=';
  }
  return out;
}

void write_png_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<uint8_t>*>(context);
  const auto* p = static_cast<const uint8_t*>(data);
  out->insert(out->end(), p, p + size);
}

void finish(GltfDoc& doc) { doc.json["buffers"][0]["byteLength"] = doc.bin.size(); }

}  // namespace

TempDir::TempDir() {
  std::random_device rd;
  path = std::filesystem::temp_directory_path() / ("foveart_engine_test_" + std::to_string(rd()) + std::to_string(rd()));
  std::filesystem::create_directories(path);
}
TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
}

int add_view(GltfDoc& doc, const std::vector<uint8_t>& bytes) {
  while (doc.bin.size() % 4) doc.bin.push_back(0);
  const size_t offset = doc.bin.size();
  doc.bin.insert(doc.bin.end(), bytes.begin(), bytes.end());
  doc.json["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes.size()}});
  return static_cast<int>(doc.json["bufferViews"].size() - 1);
}

GltfDoc unit_quad(bool textured) {
  GltfDoc doc;
  doc.json = {{"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", {0}}}}},
              {"nodes", {{{"mesh", 0}}}}, {"buffers", {nlohmann::json::object()}},
              {"bufferViews", nlohmann::json::array()}, {"accessors", nlohmann::json::array()}};
  std::vector<uint8_t> b;
  append(b, std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});
  const int vpos = add_view(doc, b);
  b.clear();
  append(b, std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  const int vnrm = add_view(doc, b);
  b.clear();
  append(b, std::vector<float>{0, 1, 1, 1, 1, 0, 0, 0});
  const int vuv = add_view(doc, b);
  b.clear();
  append(b, std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  const int vidx = add_view(doc, b);
  auto& acc = doc.json["accessors"];
  acc.push_back({{"bufferView", vpos}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"},
                 {"min", {0, 0, 0}}, {"max", {1, 1, 0}}});
  acc.push_back({{"bufferView", vnrm}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
  acc.push_back({{"bufferView", vuv}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  acc.push_back({{"bufferView", vidx}, {"componentType", 5123}, {"count", 6}, {"type", "SCALAR"}});
  nlohmann::json prim = {{"attributes", {{"POSITION", 0}, {"NORMAL", 1}, {"TEXCOORD_0", 2}}}, {"indices", 3},
                         {"material", 0}};
  doc.json["meshes"] = {{{"primitives", {prim}}}};
  nlohmann::json mat = {{"pbrMetallicRoughness", {{"baseColorFactor", {1.0, 1.0, 1.0, 1.0}}, {"metallicFactor", 0.0},
                                                  {"roughnessFactor", 1.0}}}};
  if (textured) {
    // 2x2 RGBA: red, green / blue, white.
    const uint8_t px[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    std::vector<uint8_t> png;
    stbi_write_png_to_func(&write_png_bytes, &png, 2, 2, 4, px, 8);
    const int vimg = add_view(doc, png);
    doc.json["images"] = {{{"bufferView", vimg}, {"mimeType", "image/png"}}};
    doc.json["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}}};
    doc.json["textures"] = {{{"source", 0}, {"sampler", 0}}};
    mat["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  }
  doc.json["materials"] = {mat};
  return doc;
}

std::filesystem::path write_text(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  const std::filesystem::path p = dir / name;
  std::ofstream(p, std::ios::binary) << text;
  return p;
}

std::filesystem::path write_external(const std::filesystem::path& dir, const std::string& name, GltfDoc doc) {
  finish(doc);
  doc.json["buffers"][0]["uri"] = name + ".bin";
  std::ofstream(dir / (name + ".bin"), std::ios::binary)
      .write(reinterpret_cast<const char*>(doc.bin.data()), static_cast<std::streamsize>(doc.bin.size()));
  return write_text(dir, name + ".gltf", doc.json.dump());
}

std::filesystem::path write_embedded(const std::filesystem::path& dir, const std::string& name, GltfDoc doc) {
  finish(doc);
  doc.json["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(doc.bin);
  return write_text(dir, name + ".gltf", doc.json.dump());
}

std::filesystem::path write_glb(const std::filesystem::path& dir, const std::string& name, GltfDoc doc) {
  while (doc.bin.size() % 4) doc.bin.push_back(0);
  finish(doc);
  std::string json = doc.json.dump();
  while (json.size() % 4) json += ' ';
  std::vector<uint8_t> out;
  const uint32_t total = static_cast<uint32_t>(12 + 8 + json.size() + 8 + doc.bin.size());
  append(out, std::vector<uint32_t>{0x46546C67u, 2u, total, static_cast<uint32_t>(json.size()), 0x4E4F534Au});
  out.insert(out.end(), json.begin(), json.end());
  append(out, std::vector<uint32_t>{static_cast<uint32_t>(doc.bin.size()), 0x004E4942u});
  out.insert(out.end(), doc.bin.begin(), doc.bin.end());
  const std::filesystem::path p = dir / (name + ".glb");
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size()));
  return p;
}

}  // namespace engine_test
