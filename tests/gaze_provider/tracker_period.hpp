// The sample period of the streams the gaze tests play: a 120 Hz eye tracker
// (FOVE 0).
#pragma once

#include <cstdint>

inline constexpr std::int64_t kPeriodNs = 8'333'333;
