// libFuzzer: the HID report layout parser and, with the parsed layout (or the
// default), the report decoder. Input: layout spec, a NUL byte, report bytes.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "gaze_provider/backends.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto* nul = static_cast<const std::uint8_t*>(std::memchr(data, 0, size));
  const std::size_t spec_size = nul ? std::size_t(nul - data) : size;
  const std::string spec(reinterpret_cast<const char*>(data), spec_size);
  std::string error;
  auto layout = foveart::gaze::HidReportLayout::parse(spec, &error);
  if (!layout && error.empty()) __builtin_trap();
  if (!layout) layout = foveart::gaze::HidReportLayout{};
  const std::uint8_t* report = nul ? nul + 1 : data + size;
  const std::size_t report_size = std::size_t(data + size - report);
  std::uint64_t time_us = 0, frame = 0;
  foveart::gaze::GazeSample sample;
  foveart::gaze::decode_hid_report(*layout, report, report_size, time_us, frame, sample);
  return 0;
}
