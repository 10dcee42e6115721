// The built-in scene on a small view, for the lab's tests that render it.
#pragma once

#include <render_view/render_options.hpp>
#include <eval/reference.hpp>

#include <engine/gltf_loader.hpp>
#include <engine/tracer.hpp>

#include <glm/vec2.hpp>

#include <cstdint>
#include <memory>
#include <utility>

namespace foveart::eval_test {

struct SmallScene {
  std::unique_ptr<engine::Tracer> tracer;
  FoveartEyeView view{};
  std::uint64_t hash = 0;  // the scene's content hash, as the reference cache keys it
  SmallScene(int w, int h) {
    engine::LoadResult loaded = engine::load_scene("default");
    hash = eval::scene_content_hash(*loaded.scene);
    tracer = engine::Tracer::create(std::move(*loaded.scene));
    render_view::RenderOptions o;
    o.size_px = glm::ivec2(w, h);
    view = render_view::eye_view(o, tracer->scene());
  }
};

}  // namespace foveart::eval_test
