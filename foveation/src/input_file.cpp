#include "foveation/input_file.hpp"

namespace foveart::foveation {

std::string input_file_problem(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found || status.type() == std::filesystem::file_type::none)
    return "no such file";
  if (status.type() == std::filesystem::file_type::directory) return "a directory, not a file";
  return "";
}

}  // namespace foveart::foveation
