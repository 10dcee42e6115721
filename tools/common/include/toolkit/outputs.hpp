// Checks a tool runs on its outputs before minutes of work, so that an output
// it cannot write is an error at the start (exit code 2) naming the file, not
// a failure at the end. Nothing is created but a missing output folder.
#pragma once

#include <string>

namespace foveart::toolkit {

// Whether a file can be written at `path`: its folder exists and may be written
// (the file itself is not touched). False and *error naming the file and why.
[[nodiscard]] bool check_writable_file(const std::string& path, std::string* error);

// A folder for outputs: created when missing. False and *error naming it when
// it cannot be created or written into.
[[nodiscard]] bool check_writable_dir(const std::string& path, std::string* error);

}  // namespace foveart::toolkit
