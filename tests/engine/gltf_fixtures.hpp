// Hand-made minimal glTF files for the engine tests, written to a temp dir.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace engine_test {

struct TempDir {
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::filesystem::path path;
};

// A glTF document: JSON plus the one binary buffer (buffers[0]) it refers to.
struct GltfDoc {
  nlohmann::json json;
  std::vector<uint8_t> bin;
};

// Unit quad [0,1]^2 in the plane z = 0 facing +z with TEXCOORD_0 (u = x,
// v = 1 - y) and a 2x2 PNG base colour texture when `textured`.
GltfDoc unit_quad(bool textured);

// Appends a bufferView for `bytes` (4-byte aligned) and returns its index.
int add_view(GltfDoc& doc, const std::vector<uint8_t>& bytes);

std::filesystem::path write_external(const std::filesystem::path& dir, const std::string& name, GltfDoc doc);
std::filesystem::path write_embedded(const std::filesystem::path& dir, const std::string& name, GltfDoc doc);
std::filesystem::path write_glb(const std::filesystem::path& dir, const std::string& name, GltfDoc doc);
std::filesystem::path write_text(const std::filesystem::path& dir, const std::string& name, const std::string& text);

}  // namespace engine_test
