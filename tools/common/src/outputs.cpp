// Output checks before the work (toolkit/outputs.hpp).
#include <toolkit/outputs.hpp>

#include <filesystem>
#include <system_error>

#include <unistd.h>

namespace foveart::toolkit {

namespace fs = std::filesystem;

bool check_writable_file(const std::string& path, std::string* error) {
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    *error = "cannot write " + path + ": folder " + dir.string() + " does not exist";
    return false;
  }
  if (fs::is_directory(p, ec)) {
    *error = "cannot write " + path + ": it is a folder";
    return false;
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0 || (fs::exists(p, ec) && ::access(p.c_str(), W_OK) != 0)) {
    *error = "cannot write " + path + ": permission denied";
    return false;
  }
  return true;
}

bool check_writable_dir(const std::string& path, std::string* error) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path, ec)) {
    *error = "cannot create folder " + path;
    return false;
  }
  if (::access(path.c_str(), W_OK | X_OK) != 0) {
    *error = "cannot write into " + path + ": permission denied";
    return false;
  }
  return true;
}

}  // namespace foveart::toolkit
