// Portable float maps (PFM, "PF" colour, little-endian, rows bottom to top as
// the format defines): float images that a script reads back bit for bit, so a
// metric recomputed from a written image agrees with the tool's own.
// Errors are returned as messages naming the file; nothing throws.
#pragma once

#include <foveation/image.hpp>

#include <string>

namespace foveart::tools {

std::string write_pfm(const std::string& path, const foveation::ImageRgb& image);
std::string read_pfm(const std::string& path, foveation::ImageRgb* out);

}  // namespace foveart::tools
