// Backend configurations and factories. Each backend exports only its factory; a
// factory opens the device (or file, or library) and returns nullptr plus a message
// in *error on failure. The returned provider is stopped: call start().
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "gaze_provider/filters.h"
#include "gaze_provider/gaze_provider.h"
#include "gaze_provider/host_clock.h"
#include "gaze_provider/simulator.h"

namespace foveart::gaze {

struct ReplayConfig {
  std::string path;
  // true: paced by the trace's device time, host time stamped on arrival (live playback);
  // false: as fast as possible, waits for the raw reader (lossless), recorded host times kept.
  bool original_timing = true;
  bool loop = false;            // start over at the end instead of reporting `ended`
};

struct FoveConfig {
  // dlopen()ed at run time; no build-time dependency on the FOVE SDK. Default: the
  // FOVEART_FOVE_LIBRARY environment variable, else "libFoveClient.so".
  std::string library_path;
  float low_accuracy_confidence = 0.3f;  // confidence given to Data_LowAccuracy samples
};

// Layout of one HID input report (little-endian fields).
//   spec: comma-separated key=value, for example the default
//   "id=1,size=24,time=u32@1,frame=u32@5,flags=u8@9,conf=u8@10,gaze=f32@12"
//   time: device microseconds (u32 wraps, unwrapped here; or u64);
//   flags: bit0 valid, bits 1-2 eye state (0 open, 1 closed, 2 not detected);
//   conf: u8 scaled 0..255 -> 0..1 (optional; absent = 1 for valid samples);
//   gaze: three f32 (unit vector) or three i16 scaled by 1/32767, at consecutive offsets.
struct HidReportLayout {
  int report_id = 1;  // -1: reports carry no id byte
  std::size_t size = 24;
  std::size_t time_offset = 1;
  bool time_is_u64 = false;
  std::size_t frame_offset = 5;
  std::size_t flags_offset = 9;
  std::optional<std::size_t> confidence_offset = 10;
  std::size_t gaze_offset = 12;
  bool gaze_is_i16 = false;

  // Parses a spec string; nullopt and *error on a bad spec.
  static std::optional<HidReportLayout> parse(std::string_view spec, std::string* error);
  std::string to_string() const;
};

struct HidConfig {
  std::optional<std::uint16_t> vendor_id;   // both set: match VID:PID
  std::optional<std::uint16_t> product_id;
  std::uint16_t usage_page = 0x12;          // otherwise: first device with this usage page
  std::string path;                         // explicit hidraw path wins over both
  HidReportLayout layout{};
  int read_timeout_ms = 50;
};

struct ProviderOptions {
  FilterConfig filters{};
  SimConfig sim{};
  ReplayConfig replay{};
  FoveConfig fove{};
  HidConfig hid{};
  std::size_t raw_ring_capacity = 4096;  // raw samples queued for read_raw()
  // Host time and the sim and replay backends' pacing; null: steady_host_clock().
  std::shared_ptr<HostClock> clock;
};

std::unique_ptr<GazeProvider> create_sim_provider(const SimConfig& sim, const ProviderOptions& options,
                                                  std::string* error);
std::unique_ptr<GazeProvider> create_replay_provider(const ReplayConfig& replay,
                                                     const ProviderOptions& options,
                                                     std::string* error);
std::unique_ptr<GazeProvider> create_fove_provider(const FoveConfig& fove, const ProviderOptions& options,
                                                   std::string* error);
std::unique_ptr<GazeProvider> create_hid_provider(const HidConfig& hid, const ProviderOptions& options,
                                                  std::string* error);

// Decodes one report with `layout`; false when the report is too short or has
// another report id. Fills device time (unwrapped by the caller), frame, validity,
// eye state, confidence and combined direction.
bool decode_hid_report(const HidReportLayout& layout, const std::uint8_t* data, std::size_t size,
                       std::uint64_t& out_time_us, std::uint64_t& out_frame, GazeSample& out);

// The FOVE client library path that create_fove_provider would use for `config`.
std::string fove_library_path(const FoveConfig& config);

}  // namespace foveart::gaze
