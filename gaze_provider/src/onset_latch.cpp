// Events between two looks at the gaze, from the onset times the filter chain carries.
#include "gaze_provider/onset_latch.h"

namespace foveart::gaze {

namespace {
// An onset time of 0 means "none yet" (or a chain restarted after a disconnect): no event.
bool changed_to_an_onset(std::int64_t onset_ns, std::int64_t seen_ns) noexcept {
  return onset_ns != 0 && onset_ns != seen_ns;
}
}  // namespace

OnsetLatch::Began OnsetLatch::update(const GazeSample& newest) noexcept {
  Began began;
  if (primed_) {
    began.saccade = changed_to_an_onset(newest.saccade_onset_device_ns, saccade_onset_device_ns_);
    began.hold = changed_to_an_onset(newest.hold_onset_device_ns, hold_onset_device_ns_);
  }
  primed_ = true;
  saccade_onset_device_ns_ = newest.saccade_onset_device_ns;
  hold_onset_device_ns_ = newest.hold_onset_device_ns;
  return began;
}

}  // namespace foveart::gaze
