// The default directory of FoveaRT's table caches, one rule for the layer and
// every tool.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace foveart::foveation {

// $XDG_CACHE_HOME/foveart (an absolute XDG_CACHE_HOME), else $HOME/.cache/foveart,
// else the per-user /tmp/foveart-<uid>: created mode 0700 and refused when it
// is a symlink, not a directory, owned by another user or group/world-writable
// (another user could plant files or links there). nullopt with *why naming
// the directory and the reason: the caller then runs without a cache.
std::optional<std::filesystem::path> default_cache_dir(std::string* why);

// The /tmp/foveart-<uid> rule alone, for `dir`: creates it 0700 when missing;
// nullopt with *why when it is not a private directory of this user.
std::optional<std::filesystem::path> private_cache_dir(const std::filesystem::path& dir, std::string* why);

}  // namespace foveart::foveation
