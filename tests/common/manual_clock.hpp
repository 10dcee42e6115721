// The gaze provider's tests drive it on a virtual host clock: time moves only when the
// test moves it (gaze_provider/stepped_clock.h, the clock the layer steps under a
// virtual runtime clock), so pass/fail checks follow virtual time, never the machine's
// scheduler.
#pragma once

#include "gaze_provider/stepped_clock.h"

namespace foveart::test {

using ManualClock = gaze::SteppedClock;

// Releases the clock when it goes out of scope: declared after the provider, it
// runs before the provider's destructor stops the sampling thread.
struct ReleaseAtExit {
  ManualClock& clock;
  ~ReleaseAtExit() { clock.release(); }
};

}  // namespace foveart::test
