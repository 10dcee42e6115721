// `fovea-eval motion`: a sequence of frames following a scripted head and gaze
// motion, for the full render and/or the foveated view with each TAA mode
// asked for at equal rays, measured per ring against the converged reference
// sequence, with the temporal goal of every TAA track against TAA off.
#pragma once

#include "render_options.hpp"

#include <iosfwd>

namespace CLI {
class App;
}

namespace foveart::eval {

void register_motion(CLI::App& app);

// Runs the command for these options (options.motion: "builtin" or a CSV
// file); prints the report (JSON or text) to `out` and problems to `err`.
// Returns the process exit code: 0 on success, 2 for bad options.
int run_motion(const tools::RenderOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::eval
