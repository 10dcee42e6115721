// Frame capture (FOVEART_SIM_CAPTURE_DIR): PNG per submitted projection view and
// one CSV row of timing per frame, so tests and users can see what was shown.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace foveart::sim {

struct FrameTiming {
  uint64_t frame = 0;
  int64_t wait_return_ns = 0;
  int64_t predicted_display_ns = 0;
  int64_t begin_ns = 0;
  int64_t end_ns = 0;
  int64_t submitted_display_ns = 0;
  uint32_t layers = 0;
  uint32_t projection_views = 0;
  uint32_t views_captured = 0;
  bool gaze_valid = false;
  // The gaze sample at the submitted display time, in the trace's head space
  // (+z forward, gaze_provider/trace_csv.h), so frames.csv compares with the trace.
  float gaze_x = 0.0F, gaze_y = 0.0F, gaze_z = 1.0F;
};

class FrameCapture {
 public:
  FrameCapture() = default;
  FrameCapture(const FrameCapture&) = delete;
  FrameCapture& operator=(const FrameCapture&) = delete;
  ~FrameCapture();

  // Creates dir (and parents) and frames.csv; false with a message on failure.
  [[nodiscard]] bool open(const std::string& dir, uint32_t every, std::string* error);
  bool wants_images(uint64_t frame) const { return every_ != 0 && frame % every_ == 0; }
  // frame_000012_left.png; layer_index > 0 adds "_layerK"; views beyond 2 are "_viewN".
  std::string image_path(uint64_t frame, uint32_t layer_index, uint32_t view_index) const;
  // texels: w*h*4 bytes, RGBA or BGRA order; alpha is dropped.
  bool write_png(const std::string& path, const std::vector<uint8_t>& texels, uint32_t w,
                 uint32_t h, bool bgra) const;
  void write_row(const FrameTiming& t);

 private:
  std::string dir_;
  uint32_t every_ = 1;
  std::FILE* csv_ = nullptr;
};

}  // namespace foveart::sim
