#include "config.h"

#include <cerrno>
#include <cstdlib>

#include "sim_runtime/sim_env.h"

namespace foveart::sim {
namespace {

const char* get(const char* name) {
  const char* v = std::getenv(name);
  return (v != nullptr && *v != '\0') ? v : nullptr;
}

bool parse_u64(const char* text, uint64_t& out) {
  if (text[0] == '-' || text[0] == '+') return false;
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0') return false;
  out = v;
  return true;
}

}  // namespace

std::optional<Config> config_from_environment(std::string* error) {
  Config c;
  auto bad = [&](const char* name, const char* value, const char* expected) {
    *error = std::string(name) + "='" + value + "' is not valid: expected " + expected;
    return std::nullopt;
  };
  if (const char* v = get(env::kFrames)) {
    if (!parse_u64(v, c.frame_budget)) return bad(env::kFrames, v, "a frame count >= 0");
  }
  if (const char* v = get(env::kClock)) {
    const std::string s = v;
    if (s == "virtual")
      c.virtual_clock = true;
    else if (s != "real")
      return bad(env::kClock, v, "'real' or 'virtual'");
  }
  if (const char* v = get(env::kGaze)) c.gaze_file = v;
  if (const char* v = get(env::kEyeTracking)) {
    const std::string s = v;
    if (s == "0")
      c.eye_tracking = false;
    else if (s != "1")
      return bad(env::kEyeTracking, v, "'0' or '1'");
  }
  if (const char* v = get(env::kHead)) {
    const std::string s = v;
    if (s == "sway")
      c.head_sway = true;
    else if (s != "static")
      return bad(env::kHead, v, "'static' or 'sway'");
  }
  if (const char* v = get(env::kMotion)) c.motion = v;
  if (const char* v = get(env::kMotionSeed)) {
    if (!parse_u64(v, c.motion_seed)) return bad(env::kMotionSeed, v, "an integer seed >= 0");
  }
  if (const char* v = get(env::kCaptureDir)) c.capture_dir = v;
  if (const char* v = get(env::kCaptureEvery)) {
    uint64_t n = 0;
    if (!parse_u64(v, n) || n == 0 || n > 1000000)
      return bad(env::kCaptureEvery, v, "an integer >= 1");
    c.capture_every = static_cast<uint32_t>(n);
  }
  if (const char* v = get(env::kFormats)) {
    const std::string s = v;
    if (s == "8bit" || s == "float")
      c.float_formats_only = s == "float";
    else
      return bad(env::kFormats, v, "'8bit' or 'float'");
  }
  if (const char* v = get(env::kLog)) {
    const std::string s = v;
    if (s == "0" || s == "1" || s == "2")
      c.log_level = s[0] - '0';
    else
      return bad(env::kLog, v, "0, 1 or 2");
  }
  return c;
}

}  // namespace foveart::sim
