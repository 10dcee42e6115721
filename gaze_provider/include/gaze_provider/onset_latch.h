// OnsetLatch: the saccades and blinks that began since a consumer last looked.
//
// A consumer that reads the gaze once a frame sees a sample's in_saccade/held state
// at display time only. A saccade's flag lasts ~40 ms (5 samples at 120 Hz), so one
// that falls between two 70 Hz frames, or between two slow frames, would pass
// unseen, and a history built before the gaze moved would be carried on after it.
// Every filtered sample carries the onset times of the current or last saccade and
// hold (filters.h); a new onset time means a new event, however short it was.
//
// Threads: single-threaded (one latch per consumer, e.g. per session).
#pragma once

#include <cstdint>

#include "gaze_provider/gaze_sample.h"

namespace foveart::gaze {

class OnsetLatch {
 public:
  struct Began {
    bool saccade = false;  // a saccade began since the previous update()
    bool hold = false;     // a hold (blink, dropout) began since the previous update()
  };
  // `newest`: the provider's newest filtered sample. The first call only takes note:
  // what began before a consumer's first look is not news to it.
  Began update(const GazeSample& newest) noexcept;

 private:
  bool primed_ = false;
  std::int64_t saccade_onset_device_ns_ = 0;
  std::int64_t hold_onset_device_ns_ = 0;
};

}  // namespace foveart::gaze
