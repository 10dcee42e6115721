// `fovea-eval accuracy`: one still view rendered as `fovea render` renders it
// (the full render and/or the foveated view, the foveated one over --frames
// frames with the history of its TAA mode), each measured per eccentricity ring
// against a converged reference (reference.hpp) or a reference image. The
// product's `fovea render` reports speed; how close its images come to the
// truth is measured here. The CPU engine traces, as everywhere in the lab.
#pragma once

#include <eval/lab_options.hpp>

#include <render_view/render_options.hpp>

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace foveart::eval {

struct AccuracyOptions {
  render_view::RenderOptions render;  // the view and the render, as `fovea render` takes them
  ReferenceChoice reference;          // a count (--reference-spp) or a file (--reference) is required
  std::string taa = "off";            // one of the lab's TAA modes (taa_modes.hpp)
  bool taa_mean_while_young = false;  // TaaOptions::mean_while_young
};

void register_accuracy(CLI::App& app);

// Runs the command; prints the report (JSON or text) to `out` and problems to
// `err`. Returns the process exit code: 0, 2 for bad options, 1 when the
// scene, the engine, the reference or an output fails.
int run_accuracy(const AccuracyOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::eval
