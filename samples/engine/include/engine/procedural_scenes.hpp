// Interiors generated in code for the benchmark set, each with a camera inside
// at eye height (a VR user stands in a scene), lit in glTF's photometric units
// (KHR_lights_punctual: candela for point and spot lights).
//   room   a furnished 8 x 10 m room under twelve 108 cd point lights, no sky
//   hall   a 30 m textured hall (tiles, panels) under spot lights, open to the sky at its end
//   dense  a room holding 600 spheres (about 350k triangles) under four point lights
#pragma once

#include <engine/scene.hpp>

#include <optional>
#include <string>
#include <vector>

namespace foveart::engine {

Scene make_lit_room();
Scene make_textured_hall();
Scene make_dense_room();

// The names load_scene takes for them.
const std::vector<std::string>& procedural_scene_names();
// The scene of that name; nullopt for any other name.
std::optional<Scene> make_procedural_scene(const std::string& name);

}  // namespace foveart::engine
