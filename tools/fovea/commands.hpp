// Subcommands of the fovea tool: pointset, interpolate, reconstruct and render,
// the product's; the lab's commands are fovea-eval's (eval/). Each command's
// run_<name> returns the process exit code and throws nothing: 0; 2 for bad
// options or an output it cannot write, found before any work; 1 when the
// work fails; each problem one "fovea <command>: ..." line naming the option
// or the file. Its registration turns a non-zero code into CLI::RuntimeError,
// so main exits with it; a malformed option value is CLI11's parse error.
#pragma once

#include <CLI/CLI.hpp>

namespace foveart::fovea {

void register_pointset(CLI::App& app);
void register_interpolate(CLI::App& app);
void register_reconstruct(CLI::App& app);
void register_render(CLI::App& app);

}  // namespace foveart::fovea
