// glTF 2.0 loading (tinygltf): .gltf with external or embedded (data URI)
// buffers and .glb. Every triangle primitive of the default scene's node
// hierarchy is flattened into tracking space; materials, base colour
// textures, KHR_lights_punctual, KHR_materials_transmission/_ior and the first
// camera are kept. Bad input never throws: the result carries an error that
// names the file and the problem.
#pragma once

#include <engine/scene.hpp>

#include <optional>
#include <string>

namespace foveart::engine {

struct LoadResult {
  std::optional<Scene> scene;  // set on success
  std::string error;           // "<file>: <problem>" on failure
  bool ok() const { return scene.has_value(); }
};

LoadResult load_gltf(const std::string& path);

// "default" (or empty) gives the built-in scene, "room", "hall" and "dense" the
// procedural interiors (procedural_scenes.hpp), anything else is a glTF file.
LoadResult load_scene(const std::string& spec);

}  // namespace foveart::engine
