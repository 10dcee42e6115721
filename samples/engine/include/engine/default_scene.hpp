// The built-in scene, generated in code (no download): the thesis's hard case
// for foveation — dark pillars against a bright back wall, bright ceiling light
// panels, point lights casting sharp shadows on a lit floor — plus a reflective
// floor, a glass sphere and textured (checker, brick) surfaces.
//
// Composition: the view centre (where a centred gaze rests, and where the thesis
// places its hard case) looks between two dark pillars of a cross colonnade at
// the glowing far wall, under the ceiling lights; the glass sphere stands far
// left (~38 deg from the centre, between the left pillars and the wall), the
// crate lower right, the mirror floor fills the lower part of the view.
#pragma once

#include <engine/scene.hpp>

#include <glm/vec3.hpp>

namespace foveart::engine {

Scene make_default_scene();

// World-space points on the default scene's features, to aim a gaze at them
// (benchmarks and docs measure the centred gaze, the glass and the floor).
struct DefaultSceneLandmarks {
  glm::vec3 pillar_edge;   // inner edge of the left centre pillar, at eye height
  glm::vec3 glass_centre;  // centre of the glass sphere
  glm::vec3 floor_point;   // a lit spot of the polished floor, clear of objects
};
DefaultSceneLandmarks default_scene_landmarks();

}  // namespace foveart::engine
