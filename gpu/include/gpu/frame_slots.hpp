// Frames in flight on the device path (docs/gpu.md "A pipelined frame"):
// every buffer a frame writes and the host fills or reads (uploads, status,
// timestamps, per-frame outputs) exists once per frame slot; the histories
// (image history pair, the render cache's kept rays) and the tables are
// shared by all slots, ordered by the queue. Frame n uses slot n % kFrameSlots;
// the host reuses a slot only after that slot's previous submission finished,
// kFrameSlots frames later.
#pragma once

#include <cstdint>

namespace foveart::gpu {

inline constexpr std::uint32_t kFrameSlots = 2;

}  // namespace foveart::gpu
