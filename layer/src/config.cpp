#include "config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include <foveation/content_density.hpp>
#include <foveation/display_transform.hpp>
#include <foveation/executor.hpp>

#ifndef FOVEART_SYSTEM_CONFIG_DIR
#define FOVEART_SYSTEM_CONFIG_DIR "/etc/xdg/foveart"
#endif

namespace foveart::layer {
namespace {

using nlohmann::json;

// A value as the file wrote it, for warnings (strings escaped, long values cut).
std::string shown(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// Reads each key on its own: whatever a value is (wrong type, out of range,
// anything nlohmann throws on it), the warning names the key and the value
// and the key keeps its default.
struct Reader {
  std::string_view origin;
  std::vector<std::string>* warnings;

  void warn(std::string_view key, std::string_view what) const {
    std::ostringstream s;
    s << "config " << origin << ": key '" << key << "' " << what << "; using the default";
    warnings->push_back(s.str());
  }

  // Calls read(value) when `key` is present; read returns an empty string or
  // what is wrong with the value.
  template <class ReadFn>
  void read(const json& obj, const char* key, ReadFn&& read) const {
    const auto it = obj.find(key);
    if (it == obj.end()) return;
    std::string wrong;
    try {
      wrong = read(*it);
    } catch (const json::exception& e) {
      wrong = std::string("cannot be read (") + e.what() + ")";
    }
    if (!wrong.empty()) warn(key, wrong + " (got " + shown(*it) + ")");
  }

  void read_bool(const json& obj, const char* key, bool* out) const {
    read(obj, key, [&](const json& v) -> std::string {
      if (!v.is_boolean()) return "must be true or false";
      *out = v.get<bool>();
      return {};
    });
  }

  // Integers only (1.0 is not one); checked in 64 bits before narrowing.
  void read_uint(const json& obj, const char* key, uint32_t lo, uint32_t hi, uint32_t* out) const {
    read(obj, key, [&](const json& v) -> std::string {
      const std::string wrong = "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi);
      // Non-negative integers are stored unsigned, negative ones signed.
      if (v.is_number_unsigned()) {
        const auto u = v.get<uint64_t>();
        if (u < lo || u > hi) return wrong;
        *out = static_cast<uint32_t>(u);
        return {};
      }
      if (v.is_number_integer()) {
        const auto i = v.get<int64_t>();
        if (i < int64_t{lo} || i > int64_t{hi}) return wrong;
        *out = static_cast<uint32_t>(i);
        return {};
      }
      return wrong;
    });
  }

  // Checked after the conversion to float: a double that rounds to 0 or
  // overflows a float is out of range, as is NaN.
  void read_float(const json& obj, const char* key, float lo, float hi, float* out) const {
    read(obj, key, [&](const json& v) -> std::string {
      std::ostringstream wrong;
      wrong << "must be a number in (" << lo << ", " << hi << "]";
      if (!v.is_number()) return wrong.str();
      const double d = v.get<double>();
      if (!(std::abs(d) <= double{std::numeric_limits<float>::max()})) return wrong.str();  // NaN too
      const float f = static_cast<float>(d);
      if (!(std::isfinite(f) && f > lo && f <= hi)) return wrong.str();
      *out = f;
      return {};
    });
  }

  // A number in [0, hi], where 0 turns the setting off (as opposed to leaving it to its default).
  template <typename Setting>  // float, or std::optional<float> where unset means the default
  void read_in_range_or_off(const json& obj, const char* key, double hi, Setting* out) const {
    read(obj, key, [&](const json& v) -> std::string {
      if (!v.is_number() || !(v.get<double>() >= 0.0 && v.get<double>() <= hi)) {
        std::ostringstream wrong;
        wrong << "must be a number in [0, " << hi << "]";
        return wrong.str();
      }
      *out = static_cast<float>(v.get<double>());
      return {};
    });
  }

  void read_string(const json& obj, const char* key, std::initializer_list<std::string_view> allowed,
                   std::string* out) const {
    read(obj, key, [&](const json& v) -> std::string {
      if (!v.is_string()) return "must be a string";
      const auto& s = v.get_ref<const std::string&>();
      if (allowed.size() == 0) {
        *out = s;
        return {};
      }
      for (std::string_view a : allowed) {
        if (s == a) {
          *out = s;
          return {};
        }
      }
      std::string list;
      for (std::string_view a : allowed) list += (list.empty() ? "" : "|") + std::string(a);
      return "must be one of " + list;
    });
  }

  // Keys an earlier config held (kRemovedConfigKeys): a warning each, "worker_threads" read
  // into "threads" and the old temporal switch and history ("taa", "taa_history") into "temporal" when this object
  // does not name the new key.
  void read_removed_keys(const json& obj, LayerConfig* c) const {
    for (const RemovedConfigKey& removed : kRemovedConfigKeys) {
      if (obj.contains(removed.key)) {
        warnings->push_back("config " + std::string(origin) + ": key '" + std::string(removed.key) +
                            "' was removed; replaced by " + std::string(removed.replaced_by));
      }
    }
    if (!obj.contains("threads")) read_uint(obj, "worker_threads", 0, foveation::kMaxExecutorThreads, &c->threads);
    if (obj.contains("temporal") || !(obj.contains("taa") || obj.contains("taa_history"))) return;
    const auto taa = obj.find("taa");
    const auto history = obj.find("taa_history");
    if (taa != obj.end() && taa->is_boolean() && !taa->get<bool>()) {
      c->temporal = "off";
    } else if (history != obj.end() && history->is_string()) {
      c->temporal = history->get_ref<const std::string&>().rfind("ray_cache", 0) == 0 ? "rays" : "image";
    } else if (taa != obj.end() && taa->is_boolean()) {
      c->temporal = "image";
    } else {
      return;
    }
    warnings->push_back("config " + std::string(origin) + ": read the removed keys taa / taa_history as \"temporal\": \"" +
                        c->temporal + "\"");
  }

  void apply(const json& obj, LayerConfig* c, bool top_level) const {
    for (const auto& item : obj.items()) {
      bool known = false;
      for (std::string_view k : kConfigKeys) known = known || item.key() == k;
      for (const RemovedConfigKey& removed : kRemovedConfigKeys) known = known || item.key() == removed.key;
      if (!known || (!top_level && item.key() == "applications")) {
        warnings->push_back("config " + std::string(origin) + ": unknown key '" + item.key() + "' ignored");
      }
    }
    read_bool(obj, "enabled", &c->enabled);
    read(obj, "log_level", [&](const json& v) -> std::string {
      if (!v.is_string() || !parse_log_level(v.get<std::string>(), &c->log_level)) {
        return "must be one of error|warn|info|debug";
      }
      return {};
    });
    read_string(obj, "log_file", {}, &c->log_file);
    read_string(obj, "interpolation", {"nearest", "msm", "rbf"}, &c->interpolation);
    read_uint(obj, "k", 1, 20, &c->k);
    read_float(obj, "density_scale", 0.0f, 16.0f, &c->density_scale);
    read_in_range_or_off(obj, "content_contrast", 1.0, &c->content_contrast);
    read_in_range_or_off(obj, "content_rays", 1.0, &c->content_rays);
    read_in_range_or_off(obj, "content_rays_doubling_deg", foveation::kMaxRaysDoublingEccDeg,
                         &c->content_rays_doubling_deg);
    read_uint(obj, "rays_per_point", 1, 64, &c->rays_per_point);
    read_removed_keys(obj, c);
    read_string(obj, "temporal", {"auto", "off", "image", "rays"}, &c->temporal);
    read_string(obj, "gaze_source", {"none", "provider", "eye_gaze_interaction"}, &c->gaze_source);
    read_string(obj, "gaze_provider", {}, &c->gaze_provider);
    read_string(obj, "gaze_clock", {"steady", "display_time"}, &c->gaze_clock);
    read_uint(obj, "threads", 0, foveation::kMaxExecutorThreads, &c->threads);
    read_string(obj, "cache_dir", {}, &c->cache_dir);
    read_bool(obj, "wait_for_tables", &c->wait_for_tables);
    read_string(obj, "reconstruction", {"auto", "gpu", "cpu"}, &c->reconstruction);
    read_float(obj, "exposure", 0.0f, foveation::kMaxExposure, &c->exposure);
    read_string(obj, "tone_map", {"none", "pbr-neutral", "aces"}, &c->tone_map);
  }
};

// nlohmann's parser stops at a number that does not fit a double (1e400):
// json::out_of_range 406, for the whole file. This SAX pass finds where
// parsing stops, on which token and under which keys, so that such a number
// can be dropped from its key alone and every other error located.
class ErrorLocator final : public json::json_sax_t {
 public:
  struct Level {
    bool array = false;
    std::string key;          // object: the key being read
    std::size_t index = 0;    // array: values read so far
  };
  std::vector<Level> path;    // at the error: the containers it lies in
  std::size_t end_byte = 0;   // at the error: one past the offending token
  std::string token;
  std::string what;
  int id = 0;

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    path.emplace_back();
    return true;
  }
  bool key(string_t& k) override {
    path.back().key = k;
    return true;
  }
  bool end_object() override {
    path.pop_back();
    return value();
  }
  bool start_array(std::size_t) override {
    path.push_back({true, {}, 0});
    return true;
  }
  bool end_array() override {
    path.pop_back();
    return value();
  }
  bool parse_error(std::size_t byte, const std::string& last_token, const json::exception& e) override {
    end_byte = byte;
    token = last_token;
    what = e.what();
    id = e.id;
    return false;
  }

  // "applications.hello_xr.k"; arrays as "[2]".
  std::string dotted() const {
    std::string s;
    for (const Level& l : path) {
      if (l.array) s += "[" + std::to_string(l.index) + "]";
      else s += (s.empty() ? "" : ".") + l.key;
    }
    return s;
  }

 private:
  bool value() {
    if (!path.empty() && path.back().array) ++path.back().index;
    return true;
  }
};

// Parses `text` into *out_root. A number too large for a double is replaced
// by a warning naming its key and the default (the key is removed); any other
// error rejects the file with a warning naming it and the position.
bool parse_config(std::string text, std::string_view origin, json* out_root, std::vector<std::string>* warnings) {
  const std::string where = "config " + std::string(origin) + ": ";
  std::vector<json::json_pointer> dropped;
  constexpr int kMaxDroppedNumbers = 64;  // each costs one more parse of a small file
  for (int round = 0;; ++round) {
    ErrorLocator loc;
    try {
      if (json::sax_parse(text, &loc)) break;
    } catch (const json::exception& e) {  // sax_parse reports through parse_error; this is a backstop
      loc.what = e.what();
      loc.id = 0;
    }
    const std::size_t begin = loc.end_byte - std::min(loc.end_byte, loc.token.size());
    const bool number_overflow = loc.id == 406 && !loc.path.empty() && !loc.path.back().array &&
                                 round < kMaxDroppedNumbers && loc.end_byte <= text.size() &&
                                 text.compare(begin, loc.token.size(), loc.token) == 0;
    if (!number_overflow) {
      warnings->push_back(where + "not valid JSON at byte " + std::to_string(loc.end_byte) + " (" + loc.what +
                          "); using defaults");
      return false;
    }
    warnings->push_back(where + "key '" + loc.dotted() + "' is out of range for a number (got " + loc.token +
                        "); using the default");
    json::json_pointer key_pointer;
    for (const auto& level : loc.path) {
      if (level.array) key_pointer /= level.index;
      else key_pointer /= level.key;
    }
    dropped.push_back(key_pointer);
    text.replace(begin, loc.token.size(), "null");
  }
  try {
    *out_root = json::parse(text);
    for (const auto& key_pointer : dropped) out_root->at(key_pointer.parent_pointer()).erase(key_pointer.back());
  } catch (const json::exception& e) {
    warnings->push_back(where + "not valid JSON (" + e.what() + "); using defaults");
    return false;
  }
  return true;
}

std::optional<std::string> read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

GetEnvFn process_env() {
  return [](const char* name) -> std::optional<std::string> {
    const char* v = std::getenv(name);
    if (v == nullptr) return std::nullopt;
    return std::string(v);
  };
}

void apply_config_text(std::string_view text, std::string_view origin, std::string_view application_name,
                       ConfigResult* inout_result) {
  const Reader reader{origin, &inout_result->warnings};
  json root;
  if (!parse_config(std::string(text), origin, &root, &inout_result->warnings)) return;
  if (!root.is_object()) {
    inout_result->warnings.push_back("config " + std::string(origin) +
                                     ": top level must be a JSON object; using defaults");
    return;
  }
  reader.apply(root, &inout_result->config, true);
  if (!root.contains("applications")) return;
  const json& apps = root.at("applications");
  if (!apps.is_object()) {
    reader.warn("applications", "must be an object keyed by application name");
    return;
  }
  const std::string app(application_name);
  if (!apps.contains(app)) return;
  const json& section = apps.at(app);
  if (!section.is_object()) {
    reader.warn("applications." + app, "must be an object");
    return;
  }
  const std::string app_origin = std::string(origin) + " [applications." + app + "]";
  const Reader app_reader{app_origin, &inout_result->warnings};
  app_reader.apply(section, &inout_result->config, false);
}

ConfigResult load_config(std::string_view application_name, const GetEnvFn& env) {
  ConfigResult result;
  std::vector<std::filesystem::path> candidates;
  if (auto p = env("FOVEART_CONFIG"); p && !p->empty()) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(*p, ec))
      candidates.emplace_back(*p);
    else if (std::filesystem::exists(*p, ec))
      result.warnings.push_back("FOVEART_CONFIG names '" + *p + "', which is not a regular file; searching on");
    else
      result.warnings.push_back("FOVEART_CONFIG names '" + *p + "', which does not exist; searching on");
  }
  if (auto x = env("XDG_CONFIG_HOME"); x && !x->empty()) {
    candidates.emplace_back(std::filesystem::path(*x) / "foveart" / "config.json");
  } else if (auto h = env("HOME"); h && !h->empty()) {
    candidates.emplace_back(std::filesystem::path(*h) / ".config" / "foveart" / "config.json");
  }
  candidates.emplace_back(std::filesystem::path(FOVEART_SYSTEM_CONFIG_DIR) / "config.json");

  for (const auto& path : candidates) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) continue;
    auto text = read_file(path);
    if (!text) {
      result.warnings.push_back("config " + path.string() + ": cannot be read; using defaults");
      break;
    }
    result.path = path.string();
    apply_config_text(*text, result.path, application_name, &result);
    break;
  }
  if (auto d = env("FOVEART_DISABLE"); d && *d == "1") result.config.enabled = false;
  return result;
}

}  // namespace foveart::layer
