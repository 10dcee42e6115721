// HID report layout: parsing the spec string and decoding one report.
#include <charconv>
#include <cstring>

#include "gaze_provider/backends.h"
#include "gaze_provider/gaze_math.h"

namespace foveart::gaze {

namespace {

bool parse_size(std::string_view s, std::size_t& out) {
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc{} && p == s.data() + s.size();
}

// "u32@5" -> type "u32", offset 5
bool parse_field(std::string_view v, std::string_view& type, std::size_t& offset) {
  const std::size_t at = v.find('@');
  if (at == std::string_view::npos) return false;
  type = v.substr(0, at);
  return parse_size(v.substr(at + 1), offset);
}

// offset + width <= size, written so that an offset near 2^64 cannot wrap the sum past the check.
constexpr bool field_fits(std::size_t offset, std::size_t width_bytes, std::size_t size) noexcept {
  return width_bytes <= size && offset <= size - width_bytes;
}

template <typename T>
T read_le(const std::uint8_t* p) noexcept {
  T v;
  std::memcpy(&v, p, sizeof v);  // x86_64 and aarch64 are little-endian, as HID is
  return v;
}

}  // namespace

std::optional<HidReportLayout> HidReportLayout::parse(std::string_view spec, std::string* error) {
  HidReportLayout l;
  auto fail = [&](std::string message) -> std::optional<HidReportLayout> {
    if (error) *error = "HID report layout '" + std::string(spec) + "': " + std::move(message);
    return std::nullopt;
  };
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t comma = spec.find(',', start);
    const std::string_view item = spec.substr(start, comma == std::string_view::npos ? spec.npos : comma - start);
    start = comma == std::string_view::npos ? spec.size() + 1 : comma + 1;
    if (item.empty()) continue;
    const std::size_t eq = item.find('=');
    if (eq == std::string_view::npos) return fail("'" + std::string(item) + "' is not key=value");
    const std::string_view key = item.substr(0, eq), value = item.substr(eq + 1);
    std::string_view type;
    std::size_t offset = 0;
    if (key == "id") {
      if (value == "none") l.report_id = -1;
      else if (std::size_t id = 0; parse_size(value, id) && id <= 255) l.report_id = int(id);
      else return fail("id must be 0..255 or none");
    } else if (key == "size") {
      if (!parse_size(value, l.size) || l.size == 0 || l.size > 4096) return fail("size must be 1..4096");
    } else if (key == "time") {
      if (!parse_field(value, type, offset) || (type != "u32" && type != "u64")) return fail("time must be u32@N or u64@N");
      l.time_offset = offset;
      l.time_is_u64 = type == "u64";
    } else if (key == "frame") {
      if (!parse_field(value, type, offset) || type != "u32") return fail("frame must be u32@N");
      l.frame_offset = offset;
    } else if (key == "flags") {
      if (!parse_field(value, type, offset) || type != "u8") return fail("flags must be u8@N");
      l.flags_offset = offset;
    } else if (key == "conf") {
      if (value == "none") l.confidence_offset.reset();
      else if (parse_field(value, type, offset) && type == "u8") l.confidence_offset = offset;
      else return fail("conf must be u8@N or none");
    } else if (key == "gaze") {
      if (!parse_field(value, type, offset) || (type != "f32" && type != "i16")) return fail("gaze must be f32@N or i16@N");
      l.gaze_offset = offset;
      l.gaze_is_i16 = type == "i16";
    } else {
      return fail("unknown key '" + std::string(key) + "'");
    }
  }
  struct Field {
    const char* name;
    std::optional<std::size_t> offset;
    std::size_t width_bytes;
  };
  const Field fields[] = {{"time", l.time_offset, std::size_t(l.time_is_u64 ? 8 : 4)},
                          {"frame", l.frame_offset, 4},
                          {"flags", l.flags_offset, 1},
                          {"conf", l.confidence_offset, 1},
                          {"gaze", l.gaze_offset, std::size_t(3 * (l.gaze_is_i16 ? 2 : 4))}};
  for (const Field& f : fields) {
    if (f.offset && !field_fits(*f.offset, f.width_bytes, l.size))
      return fail(std::string(f.name) + " (" + std::to_string(f.width_bytes) + " bytes at offset " +
                  std::to_string(*f.offset) + ") lies beyond size=" + std::to_string(l.size));
  }
  return l;
}

std::string HidReportLayout::to_string() const {
  std::string s = "id=" + (report_id < 0 ? std::string("none") : std::to_string(report_id));
  s += ",size=" + std::to_string(size) + ",time=" + (time_is_u64 ? "u64@" : "u32@") + std::to_string(time_offset);
  s += ",frame=u32@" + std::to_string(frame_offset) + ",flags=u8@" + std::to_string(flags_offset);
  s += ",conf=" + (confidence_offset ? "u8@" + std::to_string(*confidence_offset) : std::string("none"));
  s += ",gaze=" + std::string(gaze_is_i16 ? "i16@" : "f32@") + std::to_string(gaze_offset);
  return s;
}

bool decode_hid_report(const HidReportLayout& l, const std::uint8_t* data, std::size_t size,
                       std::uint64_t& out_time_us, std::uint64_t& out_frame, GazeSample& out) {
  if (size < l.size) return false;
  if (l.report_id >= 0 && data[0] != std::uint8_t(l.report_id)) return false;
  out_time_us = l.time_is_u64 ? read_le<std::uint64_t>(data + l.time_offset) : read_le<std::uint32_t>(data + l.time_offset);
  out_frame = read_le<std::uint32_t>(data + l.frame_offset);
  const std::uint8_t flags = data[l.flags_offset];
  const unsigned state = (flags >> 1) & 3u;
  out.eye_state = state == 0 ? EyeState::open : state == 1 ? EyeState::closed : EyeState::not_detected;
  Vec3f d;
  if (l.gaze_is_i16) {
    d = {read_le<std::int16_t>(data + l.gaze_offset) / 32767.0f, read_le<std::int16_t>(data + l.gaze_offset + 2) / 32767.0f,
         read_le<std::int16_t>(data + l.gaze_offset + 4) / 32767.0f};
  } else {
    d = {read_le<float>(data + l.gaze_offset), read_le<float>(data + l.gaze_offset + 4),
         read_le<float>(data + l.gaze_offset + 8)};
  }
  out.valid = (flags & 1u) != 0 && is_finite(d) && length(d) > 1e-6;
  out.combined_direction = out.valid ? normalized(d) : Vec3f{0.0f, 0.0f, 1.0f};
  out.confidence = !out.valid ? 0.0f : l.confidence_offset ? data[*l.confidence_offset] / 255.0f : 1.0f;
  out.left.valid = out.right.valid = false;
  out.left.state = out.right.state = out.eye_state;
  return true;
}

}  // namespace foveart::gaze
