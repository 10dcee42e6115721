#include "toolkit/image_io.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>

#include <stb_image.h>
#include <stb_image_write.h>

#include "foveation/input_file.hpp"
#include "foveation/srgb.hpp"

namespace foveart::toolkit {

namespace {

[[nodiscard]] bool fail(std::string* error, std::string message) {
  *error = std::move(message);
  return false;
}

}  // namespace

bool write_png_u8(const std::string& path, int width, int height, int channels,
                  const std::vector<std::uint8_t>& pixels, std::string* error) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3 && channels != 4) ||
      pixels.size() != std::size_t(width) * std::size_t(height) * std::size_t(channels)) {
    return fail(error, "cannot write " + path + ": image size does not match its pixels");
  }
  errno = 0;
  if (stbi_write_png(path.c_str(), width, height, channels, pixels.data(), width * channels) == 0) {
    return fail(error, "cannot write " + path + (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string()));
  }
  return true;
}

bool write_png(const std::string& path, const foveation::ImageRgb& image, PngValues values, std::string* error) {
  if (image.rgb.size() != image.pixel_count() * 3)
    return fail(error, "cannot write " + path + ": image size does not match its pixels");
  if (values == PngValues::linear) return write_png(path, image, foveation::kClampOnly, error);
  std::vector<std::uint8_t> px(image.rgb.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    px[i] = static_cast<std::uint8_t>(std::lround(std::clamp(image.rgb[i], 0.0f, 1.0f) * 255.0f));
  return write_png_u8(path, image.width_px, image.height_px, 3, px, error);
}

bool write_png(const std::string& path, const foveation::ImageRgb& image, const foveation::DisplayTransform& display,
               std::string* error) {
  if (image.rgb.size() != image.pixel_count() * 3)
    return fail(error, "cannot write " + path + ": image size does not match its pixels");
  std::vector<std::uint8_t> px(image.rgb.size());
  for (std::size_t i = 0; i < image.pixel_count(); ++i) {
    const float* p = &image.rgb[i * 3];
    const glm::u8vec3 b = display.srgb8(glm::vec3(p[0], p[1], p[2]));
    px[i * 3] = b.r, px[i * 3 + 1] = b.g, px[i * 3 + 2] = b.b;
  }
  return write_png_u8(path, image.width_px, image.height_px, 3, px, error);
}

bool read_image(const std::string& path, PngValues values, foveation::ImageRgb* out, std::string* error) {
  if (const std::string problem = foveation::input_file_problem(path); !problem.empty())
    return fail(error, "cannot read image " + path + ": " + problem);
  int w = 0, h = 0, n = 0;
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 3);
  if (data == nullptr) {
    const char* why = stbi_failure_reason();
    return fail(error, "cannot read image " + path + ": " + (why ? why : "unknown error"));
  }
  *out = foveation::ImageRgb(w, h);
  for (std::size_t i = 0; i < out->rgb.size(); ++i) {
    const float v = float(data[i]) / 255.0f;
    out->rgb[i] = values == PngValues::linear ? foveation::srgb_to_linear(v) : v;
  }
  stbi_image_free(data);
  return true;
}

}  // namespace foveart::toolkit
