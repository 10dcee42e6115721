// `fovea render`: renders a glTF scene (or the built-in default) with the
// sample engine, at full resolution and/or foveated, and reports rays and times.
// --engine cpu|gpu: the CPU engine (Embree) or the GPU engine (Vulkan compute,
// through gpu_engine::CallbackAdapter: a device round trip per batch); the
// reconstruction is the CPU's either way. With --mode both it reports the
// speedup and what the scene's content allows (content_speedup.hpp).
// One still view, its speed; accuracy against a converged reference is the lab's
// (`fovea-eval accuracy`), and so is a sequence over a scripted motion
// (`fovea-eval motion`).
#pragma once

#include <render_view/render_options.hpp>

#include <iosfwd>

namespace CLI {
class App;
}

namespace foveart::fovea {

void register_render(CLI::App& app);

// Runs the command; prints the report (JSON or text) to `out` and problems to
// `err`. Returns the process exit code (0 on success).
int run_render(const render_view::RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::fovea
