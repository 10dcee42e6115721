// Leveled logging to stderr, prefixed "foveart-sim". Level set from FOVEART_SIM_LOG.
#pragma once

#include <cstdio>
#include <string>

namespace foveart::sim {

enum class LogLevel { Error = 0, Info = 1, Debug = 2 };

void set_log_level(int level);
bool log_enabled(LogLevel level);
void log(LogLevel level, const std::string& message);

}  // namespace foveart::sim
