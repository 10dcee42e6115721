#include "foveation/cache_dir.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <sys/stat.h>
#include <unistd.h>

namespace foveart::foveation {

std::optional<std::filesystem::path> private_cache_dir(const std::filesystem::path& dir, std::string* why) {
  auto refuse = [&](const std::string& reason) -> std::optional<std::filesystem::path> {
    *why = "cache directory " + dir.string() + " refused: " + reason;
    return std::nullopt;
  };
  if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) return refuse(std::string("cannot create: ") + std::strerror(errno));
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0) return refuse(std::string("cannot stat: ") + std::strerror(errno));
  if (S_ISLNK(st.st_mode)) return refuse("it is a symlink");
  if (!S_ISDIR(st.st_mode)) return refuse("not a directory");
  if (st.st_uid != ::geteuid()) {
    return refuse("owned by uid " + std::to_string(st.st_uid) + ", not by this user (uid " + std::to_string(::geteuid()) + ")");
  }
  if ((st.st_mode & (S_IWGRP | S_IWOTH)) != 0) return refuse("group or world writable");
  return dir;
}

std::optional<std::filesystem::path> default_cache_dir(std::string* why) {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && x[0] == '/') {
    return std::filesystem::path(x) / "foveart";
  }
  if (const char* h = std::getenv("HOME"); h != nullptr && h[0] != '\0') {
    return std::filesystem::path(h) / ".cache" / "foveart";
  }
  return private_cache_dir("/tmp/foveart-" + std::to_string(::geteuid()), why);
}

}  // namespace foveart::foveation
