// What a test reads back from a hello_foveated run: the JSON object it prints
// last with --json (after the layer's log lines) and the simulated runtime's
// captured frames (FOVEART_SIM_CAPTURE_DIR).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace foveart::layer::test {

// The JSON object starting on the output's last line that opens with '{';
// null when there is none, discarded (is_discarded()) when it does not parse.
inline nlohmann::json trailing_json(const std::string& output) {
  const auto brace = output.find("\n{");
  if (brace == std::string::npos) return nullptr;
  return nlohmann::json::parse(output.substr(brace + 1), nullptr, false);
}

// The simulated runtime's capture of frame `index`, eye "left" or "right", in `dir`.
inline std::filesystem::path captured_frame(const std::filesystem::path& dir, int index, const char* eye) {
  char name[64];
  std::snprintf(name, sizeof(name), "frame_%06d_%s.png", index, eye);
  return dir / name;
}

}  // namespace foveart::layer::test
