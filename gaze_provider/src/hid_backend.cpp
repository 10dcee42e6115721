// HID eye tracker backend through hidapi (hidraw). Device: explicit path, VID:PID,
// or the first device whose usage page is 0x12 (HID "Eye and Head Trackers").
#include <hidapi/hidapi.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "threaded_provider.h"

namespace foveart::gaze {
namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s += (*w >= 0x20 && *w < 0x7f) ? char(*w) : '?';
  return s;
}

// hid_init is not thread-safe; the library keeps it initialised for the process.
bool hid_library_ready() {
  static std::once_flag once;
  static bool ok = false;
  std::call_once(once, [] { ok = hid_init() == 0; });
  return ok;
}

// Whether `path` names the same file as `listed` (a udev symlink to a hidraw node matches it).
bool same_device_path(const std::string& path, const char* listed) {
  if (listed == nullptr) return false;
  if (path == listed) return true;
  std::error_code ec;
  return std::filesystem::equivalent(path, listed, ec);
}

// The device to open: an explicit path only when hidapi lists it (hidapi's hid_open_path
// crashes on a character device that is not hidraw, /dev/null for one), else the first
// device by VID:PID or usage page. "" with *error saying why when there is none.
std::string find_device(const HidConfig& c, std::string* error) {
  const bool by_path = !c.path.empty(), by_id = c.vendor_id && c.product_id;
  std::string found;
  std::vector<std::string> listed;  // hidapi lists a device once per usage: each path once here
  hid_device_info* list = hid_enumerate(0, 0);
  for (hid_device_info* d = list; d && found.empty(); d = d->next) {
    if (by_path) {
      if (same_device_path(c.path, d->path))
        found = c.path;
      else if (d->path && std::find(listed.begin(), listed.end(), d->path) == listed.end())
        listed.emplace_back(d->path);
    } else if (by_id ? (d->vendor_id == *c.vendor_id && d->product_id == *c.product_id)
                     : d->usage_page == c.usage_page) {
      found = d->path ? d->path : "";
    }
  }
  hid_free_enumeration(list);
  if (!found.empty() || error == nullptr) return found;
  if (by_path) {
    std::string paths;
    for (const std::string& p : listed) paths += (paths.empty() ? "" : ", ") + p;
    *error = c.path + ": not a HID device (hidapi lists " + (paths.empty() ? std::string("none") : paths) + ")";
    return found;
  }
  char what[96];
  if (by_id)
    std::snprintf(what, sizeof what, "no HID device %04x:%04x", unsigned(*c.vendor_id), unsigned(*c.product_id));
  else
    std::snprintf(what, sizeof what, "no HID device with usage page 0x%02x (Eye and Head Trackers)",
                  unsigned(c.usage_page));
  *error = what;
  return found;
}

class HidBackend final : public detail::Backend {
 public:
  HidBackend(hid_device* dev, std::string path, const HidConfig& config)
      : dev_(dev), path_(std::move(path)), config_(config) {}
  ~HidBackend() override {
    if (dev_) hid_close(dev_);
  }

  detail::PollResult poll(GazeSample& out, std::string& reason) noexcept override {
    if (!dev_ && !reopen(reason)) return detail::PollResult::disconnected;
    const std::size_t report = config_.layout.size;
    // hidraw returns one report per read; tolerate several (or a partial one) anyway.
    while (pending_.size() < report) {
      std::uint8_t buf[4096];
      const int n = hid_read_timeout(dev_, buf, sizeof buf, config_.read_timeout_ms);
      if (n < 0) {
        reason = "HID read failed on " + path_ + ": " + narrow(hid_error(dev_));
        hid_close(dev_);
        dev_ = nullptr;
        pending_.clear();
        return detail::PollResult::disconnected;
      }
      if (n == 0) return detail::PollResult::none;
      pending_.insert(pending_.end(), buf, buf + n);
    }
    std::uint64_t time_us = 0, frame = 0;
    GazeSample s;
    const bool ok = decode_hid_report(config_.layout, pending_.data(), pending_.size(), time_us, frame, s);
    pending_.erase(pending_.begin(), pending_.begin() + std::ptrdiff_t(report));
    if (!ok) {
      ++bad_reports_;
      return detail::PollResult::none;
    }
    // Unwrap a 32-bit microsecond clock (wraps every 71.6 minutes).
    if (!config_.layout.time_is_u64) {
      if (have_time_ && time_us < (last_raw_time_us_ & 0xffffffffu) && (last_raw_time_us_ & 0xffffffffu) - time_us > 0x80000000u)
        time_high_ += 0x100000000ull;
      last_raw_time_us_ = time_us;
      time_us += time_high_;
    }
    have_time_ = true;
    s.device_time_ns = static_cast<std::int64_t>(time_us * 1000);
    s.frame_id = frame;
    s.source = GazeSourceKind::hid;
    out = s;
    return detail::PollResult::sample;
  }

  GazeSourceKind kind() const noexcept override { return GazeSourceKind::hid; }
  double nominal_rate_hz() const noexcept override { return 0.0; }

 private:
  bool reopen(std::string& reason) noexcept {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::string error;
    const std::string p = find_device(config_, &error);
    if (!p.empty()) dev_ = hid_open_path(p.c_str());
    if (!dev_) {
      reason = "HID device gone: " + (error.empty() ? "cannot reopen " + p : error);
      return false;
    }
    path_ = p;
    return true;
  }

  hid_device* dev_;
  std::string path_;
  HidConfig config_;
  std::vector<std::uint8_t> pending_;
  std::uint64_t bad_reports_ = 0;
  bool have_time_ = false;
  std::uint64_t last_raw_time_us_ = 0;
  std::uint64_t time_high_ = 0;
};

}  // namespace

std::unique_ptr<GazeProvider> create_hid_provider(const HidConfig& hid, const ProviderOptions& options,
                                                  std::string* error) {
  auto fail = [&](const std::string& message) -> std::unique_ptr<GazeProvider> {
    if (error) *error = "hid: " + message;
    return nullptr;
  };
  if (!hid_library_ready()) return fail("hid_init failed");
  std::string why;
  const std::string path = find_device(hid, &why);
  if (path.empty()) return fail(why);
  hid_device* dev = hid_open_path(path.c_str());
  if (!dev) return fail("cannot open " + path + " (permissions? a udev rule must grant access to hidraw)");
  return std::make_unique<detail::ThreadedProvider>(std::make_unique<HidBackend>(dev, path, hid), options);
}

}  // namespace foveart::gaze
