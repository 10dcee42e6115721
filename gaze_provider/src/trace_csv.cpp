// Trace CSV reader and writer (format: gaze_provider/trace_csv.h).
#include "gaze_provider/trace_csv.h"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <string_view>

#include "gaze_provider/gaze_math.h"

namespace foveart::gaze {

namespace {

constexpr std::array<std::string_view, 6> kRequired = {"device_time_us", "frame_id", "valid",
                                                        "gaze_x",         "gaze_y",   "gaze_z"};

// The longest line a trace may have: its widest row (25 columns of full-precision numbers) is
// about 500 bytes. A longer one is not a trace (/dev/zero, a binary file) and is not read on.
constexpr std::size_t kMaxLineBytes = 4096;

enum class LineRead { line, end, too_long };

// std::getline that stops reading a line past kMaxLineBytes.
LineRead read_line(std::istream& in, std::string& line) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  for (;;) {
    const int c = buf->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return line.empty() ? LineRead::end : LineRead::line;
    }
    if (c == '\n') return LineRead::line;
    if (line.size() == kMaxLineBytes) return LineRead::too_long;
    line.push_back(char(c));
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

// Decimal microseconds ("8333" or "8333.333") to integer nanoseconds, exactly. Any time
// whose nanoseconds fit int64 (+-292 years) reads: device clocks count from their own
// epoch (FOVE's microsecond timestamps, a monotonic clock after months of uptime).
bool parse_time_us(std::string_view s, std::int64_t& out_ns) {
  constexpr std::int64_t kMaxNs = std::numeric_limits<std::int64_t>::max();
  bool negative = false;
  if (!s.empty() && s.front() == '-') {
    negative = true;
    s.remove_prefix(1);
  }
  const std::size_t dot = s.find('.');
  const std::string_view whole = s.substr(0, dot);
  std::string_view frac = dot == std::string_view::npos ? std::string_view{} : s.substr(dot + 1);
  if (whole.empty()) return false;
  std::int64_t us = 0;
  auto [p, ec] = std::from_chars(whole.data(), whole.data() + whole.size(), us);
  if (ec != std::errc{} || p != whole.data() + whole.size() || us < 0) return false;
  if (us > kMaxNs / 1000) return false;
  std::int64_t ns = 0;
  int digits = 0;
  for (char c : frac) {
    if (c < '0' || c > '9') return false;
    if (digits < 3) ns = ns * 10 + (c - '0');
    ++digits;
  }
  if (dot != std::string_view::npos && frac.empty()) return false;
  for (int d = digits; d < 3; ++d) ns *= 10;
  if (us * 1000 > kMaxNs - ns) return false;
  out_ns = us * 1000 + ns;
  if (negative) out_ns = -out_ns;
  return true;
}

template <typename T>
bool parse_number(std::string_view s, T& out) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc{} && p == s.data() + s.size();
}

bool parse_eye_state(std::string_view s, EyeState& out) {
  if (s == "open" || s == "0") out = EyeState::open;
  else if (s == "closed" || s == "1") out = EyeState::closed;
  else if (s == "not_detected" || s == "2") out = EyeState::not_detected;
  else return false;
  return true;
}

bool parse_bool01(std::string_view s, bool& out) {
  if (s == "1") out = true;
  else if (s == "0") out = false;
  else return false;
  return true;
}

std::string format_time_us(std::int64_t ns) {
  const bool negative = ns < 0;
  const std::uint64_t a = negative ? std::uint64_t(-(ns + 1)) + 1 : std::uint64_t(ns);
  std::string s = (negative ? "-" : "") + std::to_string(a / 1000);
  if (const std::uint64_t frac = a % 1000) {
    char buf[8];
    std::snprintf(buf, sizeof buf, ".%03llu", static_cast<unsigned long long>(frac));
    s += buf;
  }
  return s;
}

std::string format_float(float v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
  return ec == std::errc{} ? std::string(buf, p) : std::string("nan");
}

// ---- Reading: the header's columns, then each row against them ----

using Column = std::optional<std::size_t>;  // where a column is, if the header has it
using Vec3Columns = std::array<Column, 3>;

struct EyeColumns {
  Column valid;
  Vec3Columns origin, dir;
};

// The header: every column's name, and where the optional ones are.
struct TraceColumns {
  std::vector<std::string> names;  // owns its names: the line is reused for the rows
  Column host, state, conf;
  Vec3Columns target;
  std::array<EyeColumns, 2> eye;
  bool has_targets() const { return target[0] && target[1] && target[2]; }
};

// Reads the header line into `out`; returns why it is no trace header, or "".
std::string read_header(std::string line, TraceColumns& out) {
  if (line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 BOM
  for (std::string_view name : split(line)) out.names.emplace_back(name);
  for (std::size_t i = 0; i < kRequired.size(); ++i) {
    if (i >= out.names.size() || out.names[i] != kRequired[i])
      return "header column " + std::to_string(i + 1) + " must be '" + std::string(kRequired[i]) +
             "' (required columns, in order: device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z)";
  }
  std::map<std::string, std::size_t, std::less<>> optional;
  for (std::size_t i = kRequired.size(); i < out.names.size(); ++i) optional.emplace(out.names[i], i);
  auto column = [&](std::string_view name) -> Column {
    auto it = optional.find(name);
    return it == optional.end() ? std::nullopt : Column(it->second);
  };
  out.host = column("host_time_us");
  out.state = column("eye_state");
  out.conf = column("confidence");
  out.target = {column("target_x"), column("target_y"), column("target_z")};
  for (int e = 0; e < 2; ++e) {
    const std::string p = e == 0 ? "left_" : "right_";
    out.eye[e].valid = column(p + "valid");
    for (int k = 0; k < 3; ++k) {
      const std::string axis(1, char('x' + k));
      out.eye[e].origin[k] = column(p + "origin_" + axis);
      out.eye[e].dir[k] = column(p + axis);
    }
  }
  return "";
}

// One row's fields as the header names them.
struct RowFields {
  const TraceColumns& cols;
  const std::vector<std::string_view>& f;

  std::string bad(std::size_t i, const char* what) const {
    const std::string got(f[i]);
    return "column " + std::to_string(i + 1) + " '" + cols.names[i] + "': " + what + " (got '" + got + "')";
  }
  // Reads the vector's columns present into v; the first that is no number, if any.
  Column read_vec(const Vec3Columns& c, Vec3f& v) const {
    float* out[3] = {&v.x, &v.y, &v.z};
    for (int k = 0; k < 3; ++k)
      if (c[k] && !parse_number(f[*c[k]], *out[k])) return c[k];
    return std::nullopt;
  }
};

// The combined gaze: the required columns, host time, eye state and confidence.
std::optional<std::string> parse_combined(const RowFields& r, TraceRow& row) {
  const auto& f = r.f;
  const TraceColumns& c = r.cols;
  GazeSample& s = row.sample;
  s.source = GazeSourceKind::replay;
  if (!parse_time_us(f[0], s.device_time_ns)) return r.bad(0, "not a decimal number of microseconds");
  if (!parse_number(f[1], s.frame_id)) return r.bad(1, "not an unsigned integer");
  if (!parse_bool01(f[2], s.valid)) return r.bad(2, "must be 0 or 1");
  if (auto b = r.read_vec({3, 4, 5}, s.combined_direction)) return r.bad(*b, "not a number");
  if (s.valid && (!is_finite(s.combined_direction) || length(s.combined_direction) < 1e-6))
    return "valid row with a non-finite or zero gaze direction";
  if (c.host) {
    if (!parse_time_us(f[*c.host], s.host_time_ns)) return r.bad(*c.host, "not a decimal number of microseconds");
    row.has_host_time = true;
  }
  s.eye_state = s.valid ? EyeState::open : EyeState::not_detected;
  if (c.state && !parse_eye_state(f[*c.state], s.eye_state))
    return r.bad(*c.state, "must be open, closed or not_detected");
  s.confidence = s.valid ? 1.0f : 0.0f;
  if (c.conf && (!parse_number(f[*c.conf], s.confidence) || !(s.confidence >= 0.0f && s.confidence <= 1.0f)))
    return r.bad(*c.conf, "must be a number in [0, 1]");
  return std::nullopt;
}

// Each eye's gaze (its state defaults to the combined one) and the target.
std::optional<std::string> parse_eyes_and_target(const RowFields& r, TraceRow& row) {
  GazeSample& s = row.sample;
  for (int e = 0; e < 2; ++e) {
    EyeGaze& eye = e == 0 ? s.left : s.right;
    const EyeColumns& ec = r.cols.eye[e];
    if (ec.valid && !parse_bool01(r.f[*ec.valid], eye.valid)) return r.bad(*ec.valid, "must be 0 or 1");
    if (auto b = r.read_vec(ec.origin, eye.origin_m)) return r.bad(*b, "not a number");
    if (auto b = r.read_vec(ec.dir, eye.direction)) return r.bad(*b, "not a number");
    eye.state = eye.valid ? EyeState::open : s.eye_state;
  }
  if (r.cols.has_targets()) {
    Vec3f t;
    if (auto b = r.read_vec(r.cols.target, t)) return r.bad(*b, "not a number");
    if (is_finite(t) && length(t) > 1e-6) row.target = t;
  }
  return std::nullopt;
}

// A data row into `row`; why it is not a valid row, if it is not.
std::optional<std::string> parse_row(const std::vector<std::string_view>& f, const TraceColumns& cols, TraceRow& row) {
  const std::size_t n = cols.names.size();
  if (f.size() < n)
    return "truncated row: " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n);
  if (f.size() > n) return "row has " + std::to_string(f.size()) + " fields, the header has " + std::to_string(n);
  const RowFields r{cols, f};
  if (auto error = parse_combined(r, row)) return error;
  return parse_eyes_and_target(r, row);
}

}  // namespace

std::string TraceError::to_string() const {
  std::string where = file;
  if (line != 0) where += (where.empty() ? "line " : ":") + std::to_string(line);
  return where.empty() ? message : where + ": " + message;
}

std::optional<Trace> read_trace(std::istream& in, TraceError* error) {
  auto fail = [&](std::size_t line, std::string message) -> std::optional<Trace> {
    if (error) *error = TraceError{line, std::move(message), {}};
    return std::nullopt;
  };

  const std::string too_long = "a line longer than " + std::to_string(kMaxLineBytes) + " bytes: not a gaze trace";
  std::string line;
  std::size_t line_no = 1;
  const LineRead header = read_line(in, line);
  if (header == LineRead::too_long) return fail(line_no, too_long);
  if (header == LineRead::end)
    return fail(1, "empty file: expected the header line 'device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z'");
  TraceColumns cols;
  if (std::string why = read_header(line, cols); !why.empty()) return fail(1, std::move(why));

  Trace trace;
  trace.has_host_time = cols.host.has_value();
  trace.has_eye_state = cols.state.has_value();
  trace.has_targets = cols.has_targets();
  bool have_prev = false;
  std::int64_t prev_ns = 0;
  for (LineRead read; (read = read_line(in, line)) != LineRead::end;) {
    ++line_no;
    if (read == LineRead::too_long) return fail(line_no, too_long);
    if (trim(line).empty()) continue;
    TraceRow row;
    if (auto why = parse_row(split(line), cols, row)) return fail(line_no, std::move(*why));
    const GazeSample& s = row.sample;
    if (have_prev && s.device_time_ns <= prev_ns) {
      if (trace.skipped_non_monotonic++ == 0) trace.first_skipped_line = line_no;
      continue;
    }
    have_prev = true;
    prev_ns = s.device_time_ns;
    trace.rows.push_back(row);
  }
  if (in.bad()) return fail(line_no, "read error");
  return trace;
}

std::optional<Trace> read_trace_file(const std::string& path, TraceError* error) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (error) *error = TraceError{0, "a directory, not a file", path};
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    if (error) *error = TraceError{0, "cannot open for reading", path};
    return std::nullopt;
  }
  auto trace = read_trace(in, error);
  if (!trace && error) error->file = path;
  return trace;
}

TraceWriter::TraceWriter(std::ostream& out, bool with_targets) : out_(out), with_targets_(with_targets) {
  out_ << "device_time_us,frame_id,valid,gaze_x,gaze_y,gaze_z,host_time_us,eye_state,confidence";
  for (const char* eye : {"left", "right"})
    for (const char* c : {"valid", "origin_x", "origin_y", "origin_z", "x", "y", "z"}) out_ << ',' << eye << '_' << c;
  if (with_targets_) out_ << ",target_x,target_y,target_z";
  out_ << '\n';
}

void TraceWriter::write(const GazeSample& s, const std::optional<Vec3f>& target) {
  std::string line = format_time_us(s.device_time_ns) + ',' + std::to_string(s.frame_id) + ',' +
                     (s.valid ? '1' : '0');
  auto vec = [&line](const Vec3f& v) {
    line += ',' + format_float(v.x) + ',' + format_float(v.y) + ',' + format_float(v.z);
  };
  vec(s.combined_direction);
  line += ',' + format_time_us(s.host_time_ns) + ',' + to_string(s.eye_state) + ',' + format_float(s.confidence);
  for (const EyeGaze* e : {&s.left, &s.right}) {
    line += e->valid ? ",1" : ",0";
    vec(e->origin_m);
    vec(e->direction);
  }
  if (with_targets_) {
    if (target) vec(*target);
    else line += ",nan,nan,nan";
  }
  line += '\n';
  out_ << line;
}

}  // namespace foveart::gaze
