// Subcommands of the fovea tool. A command reports failure by throwing
// (CLI::ValidationError for bad arguments, std::exception otherwise): main
// prints "fovea <command>: error: <what>" and exits non-zero.
#pragma once

#include <CLI/CLI.hpp>

namespace foveart::fovea {

void register_pointset(CLI::App& app);
void register_interpolate(CLI::App& app);
void register_reconstruct(CLI::App& app);
void register_render(CLI::App& app);

}  // namespace foveart::fovea
