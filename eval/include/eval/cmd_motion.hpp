// `fovea-eval motion`: a sequence of frames following a scripted head and gaze
// motion, for the full render and/or the foveated view with each TAA mode
// asked for at equal rays, measured per ring against the converged reference
// sequence, with the temporal goal of every TAA track against TAA off.
#pragma once

#include <eval/lab_options.hpp>

#include <render_view/render_options.hpp>

#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace foveart::eval {

struct MotionOptions {
  // The view at rest and the render (--frames: the sequence's frames); the
  // motion gives the head pose and the gaze, so these take neither.
  render_view::RenderOptions render;
  // The scripted head and gaze motion ("builtin" or a CSV file): --frames frames
  // at start_s + i / fps, measured per ring against the reference sequence.
  std::string motion = "builtin";
  std::optional<double> start_s;  // default 0
  std::optional<double> fps;      // default 70
  // The foveated tracks' TAA modes, a list (off,restart,reproject), each rendered
  // as its own view at equal rays (taa_modes.hpp).
  std::string taa = "off";
  bool taa_mean_while_young = false;  // TaaOptions::mean_while_young
  ReferenceChoice reference;          // a count or none (no temporal error); no file
};

void register_motion(CLI::App& app);

// Runs the command for these options; prints the report (JSON or text) to `out`
// and problems to `err`. Returns the process exit code: 0 on success, 2 for bad options.
int run_motion(const MotionOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::eval
