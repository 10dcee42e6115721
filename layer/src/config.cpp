#include "config.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#ifndef FOVEART_SYSTEM_CONFIG_DIR
#define FOVEART_SYSTEM_CONFIG_DIR "/etc/xdg/foveart"
#endif

namespace foveart::layer {
namespace {

using nlohmann::json;

struct Reader {
  std::string_view origin;
  std::vector<std::string>* warnings;

  void warn(std::string_view key, std::string_view what) const {
    std::ostringstream s;
    s << "config " << origin << ": key '" << key << "' " << what << "; using the default";
    warnings->push_back(s.str());
  }

  void read_bool(const json& obj, const char* key, bool* out) const {
    if (!obj.contains(key)) return;
    const json& v = obj.at(key);
    if (v.is_boolean()) *out = v.get<bool>();
    else warn(key, "must be true or false");
  }

  void read_uint(const json& obj, const char* key, uint32_t lo, uint32_t hi, uint32_t* out) const {
    if (!obj.contains(key)) return;
    const json& v = obj.at(key);
    if (v.is_number_integer() && v.get<int64_t>() >= lo && v.get<int64_t>() <= hi) {
      *out = static_cast<uint32_t>(v.get<int64_t>());
    } else {
      warn(key, "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    }
  }

  void read_float(const json& obj, const char* key, float lo, float hi, float* out) const {
    if (!obj.contains(key)) return;
    const json& v = obj.at(key);
    if (v.is_number() && v.get<double>() > double{lo} && v.get<double>() <= double{hi}) {
      *out = v.get<float>();
    } else {
      std::ostringstream range;
      range << "must be a number in (" << lo << ", " << hi << "]";
      warn(key, range.str());
    }
  }

  void read_string(const json& obj, const char* key, std::initializer_list<std::string_view> allowed,
                   std::string* out) const {
    if (!obj.contains(key)) return;
    const json& v = obj.at(key);
    if (!v.is_string()) {
      warn(key, "must be a string");
      return;
    }
    const auto s = v.get<std::string>();
    if (allowed.size() == 0) {
      *out = s;
      return;
    }
    for (std::string_view a : allowed) {
      if (s == a) {
        *out = s;
        return;
      }
    }
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : "|") + std::string(a);
    warn(key, "must be one of " + list + " (got '" + s + "')");
  }

  void apply(const json& obj, LayerConfig* c, bool top_level) const {
    for (const auto& item : obj.items()) {
      bool known = false;
      for (std::string_view k : kConfigKeys) known = known || item.key() == k;
      if (!known || (!top_level && item.key() == "applications")) {
        warnings->push_back("config " + std::string(origin) + ": unknown key '" + item.key() + "' ignored");
      }
    }
    read_bool(obj, "enabled", &c->enabled);
    if (obj.contains("log_level")) {
      const json& v = obj.at("log_level");
      if (!v.is_string() || !parse_log_level(v.get<std::string>(), &c->log_level)) {
        warn("log_level", "must be one of error|warn|info|debug");
      }
    }
    read_string(obj, "log_file", {}, &c->log_file);
    read_string(obj, "interpolation", {"nearest", "shepard", "rbf"}, &c->interpolation);
    read_uint(obj, "k", 1, 20, &c->k);
    read_float(obj, "density_scale", 0.0f, 16.0f, &c->density_scale);
    read_uint(obj, "rays_per_point", 1, 64, &c->rays_per_point);
    read_bool(obj, "taa", &c->taa);
    read_string(obj, "gaze_source", {"none", "provider", "eye_gaze_interaction"}, &c->gaze_source);
    read_string(obj, "gaze_provider", {}, &c->gaze_provider);
    read_uint(obj, "worker_threads", 0, 256, &c->worker_threads);
    read_string(obj, "cache_dir", {}, &c->cache_dir);
    read_bool(obj, "wait_for_tables", &c->wait_for_tables);
  }
};

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
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    inout_result->warnings.push_back("config " + std::string(origin) + ": not valid JSON (" + e.what() +
                                     "); using defaults");
    return;
  }
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
    if (std::filesystem::exists(*p)) candidates.emplace_back(*p);
    else result.warnings.push_back("FOVEART_CONFIG names '" + *p + "', which does not exist; searching on");
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
