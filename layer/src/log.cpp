#include "log.hpp"

#include <cstdio>
#include <mutex>

namespace foveart::layer {
namespace {

struct Sink {
  ~Sink() {
    if (file != nullptr) std::fclose(file);
  }
  std::mutex mutex;
  std::atomic<int> level{static_cast<int>(LogLevel::Warn)};
  std::FILE* file = nullptr;
  std::string file_path;
};

Sink& sink() {
  static Sink instance;
  return instance;
}

}  // namespace

bool parse_log_level(std::string_view name, LogLevel* out_level) {
  static constexpr std::string_view kNames[] = {"error", "warn", "info", "debug"};
  for (int i = 0; i < 4; ++i) {
    if (name == kNames[i]) {
      *out_level = static_cast<LogLevel>(i);
      return true;
    }
  }
  return false;
}

const char* log_level_name(LogLevel level) {
  switch (level) {
    case LogLevel::Error: return "error";
    case LogLevel::Warn: return "warn";
    case LogLevel::Info: return "info";
    case LogLevel::Debug: return "debug";
  }
  return "?";
}

void log_configure(LogLevel level, const std::string& file_path) {
  Sink& s = sink();
  std::lock_guard lock(s.mutex);
  s.level.store(static_cast<int>(level), std::memory_order_relaxed);
  if (file_path == s.file_path) return;
  if (s.file != nullptr) std::fclose(s.file);
  s.file = nullptr;
  s.file_path = file_path;
  if (!file_path.empty()) {
    s.file = std::fopen(file_path.c_str(), "a");
    if (s.file == nullptr) {
      std::fprintf(stderr, "[foveart layer] warn: cannot open log file '%s'; logging to stderr only\n",
                   file_path.c_str());
    }
  }
}

bool log_enabled(LogLevel level) {
  return static_cast<int>(level) <= sink().level.load(std::memory_order_relaxed);
}

void log_write(LogLevel level, std::string_view message) {
  Sink& s = sink();
  std::lock_guard lock(s.mutex);
  std::fprintf(stderr, "[foveart layer] %s: %.*s\n", log_level_name(level),
               static_cast<int>(message.size()), message.data());
  if (s.file != nullptr) {
    std::fprintf(s.file, "%s: %.*s\n", log_level_name(level), static_cast<int>(message.size()),
                 message.data());
    std::fflush(s.file);
  }
}

}  // namespace foveart::layer
