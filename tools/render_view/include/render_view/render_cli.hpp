// The command-line options of a render, one set for the product's `fovea render`
// and the lab's `fovea-eval` commands (accuracy, motion), and the parsers of the
// values several commands take.
#pragma once

#include <render_view/render_options.hpp>

#include <functional>
#include <memory>

namespace CLI {
class App;
}

namespace foveart::render_view {

// Adds the options every render command shares to `cmd`, into *opts: the scene and
// view (--scene --preset --eye --size --fov-deg), the render (--mode
// --rays-per-point --interpolation --k --density-scale --pattern --frames
// --threads --seed --without --pixel-filter), the viewer (--look-at), the
// display (--exposure --tone-map) and the outputs (--out --cache-dir --json).
// Returns what the command's callback calls first: it parses the options given
// as text (--size, --fov-deg, --look-at) into *opts and throws CLI::ValidationError naming a bad one.
std::function<void()> add_render_options(CLI::App* cmd, const std::shared_ptr<RenderOptions>& opts);

// `fovea render`: --temporal off|image|rays, the product's one temporal choice (the layer's
// "temporal"), into opts->temporal; "rays" brings the B-spline pixel filter unless --pixel-filter is given.
void add_temporal_option(CLI::App* cmd, const std::shared_ptr<RenderOptions>& opts);

// "X,Y" -> gaze in pixels; throws CLI::ValidationError naming `option`.
glm::vec2 parse_gaze_option(const std::string& option, const std::string& text);
// "X,Y,Z" -> a point in scene space (metres); throws CLI::ValidationError naming `option`.
std::array<double, 3> parse_point_option(const std::string& option, const std::string& text);
// "X,Y,Z" -> a standing viewer (out->viewer_m), "px,py,pz,qx,qy,qz,qw" -> an exact
// eye pose (out->pose); throws CLI::ValidationError naming `option`.
void parse_pose_option(const std::string& option, const std::string& text, RenderOptions* out);

}  // namespace foveart::render_view
