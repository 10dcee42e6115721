// gaze-diag list: what is plugged in, and what could be a gaze source.
#include <dlfcn.h>
#include <hidapi/hidapi.h>
#include <libusb.h>

#include <cstdio>
#include <string>

#include "diag.h"

namespace foveart::gaze::diag {

namespace {

// Vendors whose devices are eye trackers (extend as hardware is verified).
struct KnownVendor {
  unsigned vid;
  const char* name;
};
constexpr KnownVendor kEyeTrackerVendors[] = {{0x2104, "Tobii"}};

const char* known_vendor(unsigned vid) {
  for (const KnownVendor& k : kEyeTrackerVendors)
    if (k.vid == vid) return k.name;
  return nullptr;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s += (*w >= 0x20 && *w < 0x7f) ? char(*w) : '?';
  return s;
}

std::string usb_string(libusb_device_handle* h, std::uint8_t index) {
  if (!h || index == 0) return "";
  unsigned char buf[256];
  const int n = libusb_get_string_descriptor_ascii(h, index, buf, sizeof buf);
  return n > 0 ? std::string(reinterpret_cast<char*>(buf), std::size_t(n)) : "";
}

}  // namespace

int run_list(const FoveConfig& fove, bool json) {
  std::string usb_json, hid_json;
  if (!json) std::printf("USB devices (libusb):\n");
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) {
    if (!json) std::printf("  libusb unavailable\n");
  } else {
    libusb_device** list = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    for (ssize_t i = 0; i < n; ++i) {
      libusb_device_descriptor d{};
      if (libusb_get_device_descriptor(list[i], &d) != 0) continue;
      libusb_device_handle* h = nullptr;
      const bool opened = libusb_open(list[i], &h) == 0;
      const std::string manufacturer = usb_string(h, d.iManufacturer), product = usb_string(h, d.iProduct);
      if (h) libusb_close(h);
      const char* known = known_vendor(d.idVendor);
      char line[512];
      std::snprintf(line, sizeof line, "  %04x:%04x class %02x  %s%s%s%s\n", d.idVendor, d.idProduct,
                    d.bDeviceClass, opened ? manufacturer.c_str() : "(strings unreadable: no permission)",
                    opened && !product.empty() ? " / " : "", opened ? product.c_str() : "",
                    known ? "  [eye tracker vendor]" : "");
      if (!json) std::fputs(line, stdout);
      char entry[768];
      std::snprintf(entry, sizeof entry,
                    "%s{\"vid\": \"%04x\", \"pid\": \"%04x\", \"class\": %u, \"manufacturer\": \"%s\", "
                    "\"product\": \"%s\", \"eye_tracker\": %s}",
                    usb_json.empty() ? "" : ", ", d.idVendor, d.idProduct, unsigned(d.bDeviceClass),
                    json_escape(manufacturer).c_str(), json_escape(product).c_str(), known ? "true" : "false");
      usb_json += entry;
    }
    if (n >= 0) libusb_free_device_list(list, 1);
    if (n <= 0 && !json) std::printf("  (none)\n");
    libusb_exit(ctx);
  }

  if (!json) std::printf("HID devices (hidapi/hidraw):\n");
  hid_device_info* hids = hid_init() == 0 ? hid_enumerate(0, 0) : nullptr;
  if (!hids && !json) std::printf("  (none)\n");
  for (hid_device_info* h = hids; h; h = h->next) {
    const bool eye = h->usage_page == 0x12 || known_vendor(h->vendor_id);
    const std::string product = narrow(h->product_string), manufacturer = narrow(h->manufacturer_string);
    if (!json)
      std::printf("  %04x:%04x usage page 0x%04x usage 0x%04x  %s  %s / %s%s\n", h->vendor_id, h->product_id,
                  h->usage_page, h->usage, h->path ? h->path : "", manufacturer.c_str(), product.c_str(),
                  eye ? "  [eye tracker]" : "");
    char entry[768];
    std::snprintf(entry, sizeof entry,
                  "%s{\"vid\": \"%04x\", \"pid\": \"%04x\", \"usage_page\": %u, \"usage\": %u, \"path\": \"%s\", "
                  "\"product\": \"%s\", \"eye_tracker\": %s}",
                  hid_json.empty() ? "" : ", ", h->vendor_id, h->product_id, unsigned(h->usage_page),
                  unsigned(h->usage), json_escape(h->path ? h->path : "").c_str(), json_escape(product).c_str(),
                  eye ? "true" : "false");
    hid_json += entry;
  }
  hid_free_enumeration(hids);
  hid_exit();

  const std::string path = fove_library_path(fove);
  void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  const char* why = lib ? nullptr : dlerror();
  const bool has_api = lib && dlsym(lib, "fove_createHeadset") && dlsym(lib, "fove_Headset_fetchEyeTrackingData");
  if (lib) dlclose(lib);
  if (json) {
    std::printf("{\n  \"usb\": [%s],\n  \"hid\": [%s],\n  \"fove_library\": {\"path\": \"%s\", \"loadable\": %s, "
                "\"eye_tracking_api\": %s, \"error\": \"%s\"}\n}\n",
                usb_json.c_str(), hid_json.c_str(), json_escape(path).c_str(), lib ? "true" : "false",
                has_api ? "true" : "false", json_escape(why ? why : "").c_str());
  } else {
    std::printf("FOVE client library:\n  %s: %s\n", path.c_str(),
                lib ? (has_api ? "loadable, eye-tracking entry points present" : "loadable, but not a FOVE client")
                    : (std::string("not loadable: ") + (why ? why : "unknown")).c_str());
  }
  return 0;
}

}  // namespace foveart::gaze::diag
