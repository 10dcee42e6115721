#include "frame_capture.h"

#include <stb_image_write.h>

#include <cinttypes>
#include <filesystem>
#include <system_error>

namespace foveart::sim {

FrameCapture::~FrameCapture() {
  if (csv_ != nullptr) std::fclose(csv_);
}

bool FrameCapture::open(const std::string& dir, uint32_t every, std::string* error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    *error = "capture dir '" + dir + "': " + ec.message();
    return false;
  }
  dir_ = dir;
  every_ = every;
  const std::string csv_path = (std::filesystem::path(dir) / "frames.csv").string();
  csv_ = std::fopen(csv_path.c_str(), "w");
  if (csv_ == nullptr) {
    *error = "cannot write '" + csv_path + "'";
    return false;
  }
  std::fprintf(
      csv_,
      "frame,wait_return_ns,predicted_display_ns,begin_ns,end_ns,submitted_display_ns,layers,"
      "projection_views,views_captured,gaze_valid,gaze_x,gaze_y,gaze_z\n");
  std::fflush(csv_);
  return true;
}

std::string FrameCapture::image_path(uint64_t frame, uint32_t layer_index,
                                     uint32_t view_index) const {
  char name[96];
  const char* eye = view_index == 0 ? "left" : view_index == 1 ? "right" : nullptr;
  std::string suffix = eye != nullptr ? eye : "view" + std::to_string(view_index);
  if (layer_index == 0) {
    std::snprintf(name, sizeof name, "frame_%06" PRIu64 "_%s.png", frame, suffix.c_str());
  } else {
    std::snprintf(name, sizeof name, "frame_%06" PRIu64 "_layer%u_%s.png", frame, layer_index,
                  suffix.c_str());
  }
  return (std::filesystem::path(dir_) / name).string();
}

bool FrameCapture::write_png(const std::string& path, const std::vector<uint8_t>& texels,
                             uint32_t w, uint32_t h, bool bgra) const {
  std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
  for (size_t i = 0, n = static_cast<size_t>(w) * h; i < n; ++i) {
    const uint8_t* t = &texels[i * 4];
    rgb[i * 3 + 0] = bgra ? t[2] : t[0];
    rgb[i * 3 + 1] = t[1];
    rgb[i * 3 + 2] = bgra ? t[0] : t[2];
  }
  // Fast settings: one cheap filter and low effort; captures are for inspection.
  stbi_write_png_compression_level = 1;
  stbi_write_force_png_filter = 1;  // "sub"
  return stbi_write_png(path.c_str(), static_cast<int>(w), static_cast<int>(h), 3, rgb.data(),
                        static_cast<int>(w * 3)) != 0;
}

void FrameCapture::write_row(const FrameTiming& t) {
  if (csv_ == nullptr) return;
  std::fprintf(csv_,
               "%" PRIu64 ",%" PRId64 ",%" PRId64 ",%" PRId64 ",%" PRId64 ",%" PRId64
               ",%u,%u,%u,%d,%.6f,%.6f,%.6f\n",
               t.frame, t.wait_return_ns, t.predicted_display_ns, t.begin_ns, t.end_ns,
               t.submitted_display_ns, t.layers, t.projection_views, t.views_captured,
               t.gaze_valid ? 1 : 0, static_cast<double>(t.gaze_x), static_cast<double>(t.gaze_y),
               static_cast<double>(t.gaze_z));
  std::fflush(csv_);
}

}  // namespace foveart::sim
