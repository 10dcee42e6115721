// What is wrong with a path an input is read from: one rule, one wording, for
// every reader of scenes, motion scripts and images.
#pragma once

#include <filesystem>
#include <string>

namespace foveart::foveation {

// "no such file", "a directory, not a file", or "" for anything a reader can
// open: a regular file, or a pipe or device it may stream from.
std::string input_file_problem(const std::filesystem::path& path);

}  // namespace foveart::foveation
