// Portable float maps (PFM, "PF" colour, little-endian, rows bottom to top as
// the format defines): float images that a script reads back bit for bit, so a
// metric recomputed from a written image agrees with the tool's own.
// False and *error naming the file when it cannot be written or read; nothing throws.
#pragma once

#include <foveation/image.hpp>

#include <string>

namespace foveart::eval {

[[nodiscard]] bool write_pfm(const std::string& path, const foveation::ImageRgb& image, std::string* error);
[[nodiscard]] bool read_pfm(const std::string& path, foveation::ImageRgb* out, std::string* error);

}  // namespace foveart::eval
