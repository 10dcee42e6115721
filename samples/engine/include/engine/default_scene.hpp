// The built-in scene, generated in code (no download): the thesis's hard case
// for foveation — dark pillars against a bright back wall, bright ceiling light
// panels, point lights casting sharp shadows on a lit floor — plus a reflective
// floor, a glass sphere and textured (checker, brick) surfaces.
#pragma once

#include <engine/scene.hpp>

namespace foveart::engine {

Scene make_default_scene();

}  // namespace foveart::engine
