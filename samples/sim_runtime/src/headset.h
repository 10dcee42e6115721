// The headset this runtime simulates: the one FOVE 0 description
// (foveation/device.hpp) that the foveation tables and the sample engine read
// too, so the views the runtime reports are the display the tables are built for.
#pragma once

#include <foveation/device.hpp>

namespace foveart::sim {

inline const foveation::HeadsetDescription& headset() {
  static const foveation::HeadsetDescription kFove0 = foveation::fove0();
  return kFove0;
}

}  // namespace foveart::sim
