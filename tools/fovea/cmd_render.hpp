// `fovea render`: renders a glTF scene (or the built-in default) with the
// sample engine, at full resolution and/or foveated, and reports rays and times.
// --engine cpu|gpu: the CPU engine (Embree) or the GPU engine (Vulkan compute,
// through gpu_engine::CallbackAdapter: a device round trip per batch); the
// reconstruction is the CPU's either way.
// One still view; a sequence over a scripted motion is `fovea-eval motion`.
#pragma once

#include "render_options.hpp"

#include <iosfwd>

namespace CLI {
class App;
}

void register_render(CLI::App& app);

namespace foveart::tools {

// Runs the command; prints the report (JSON or text) to `out` and problems to
// `err`. Returns the process exit code (0 on success).
int run_render(const RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::tools
