#include <toolkit/machine.hpp>

#include <sys/utsname.h>

#include <fstream>
#include <thread>

#ifndef FOVEART_BUILD_TYPE
#define FOVEART_BUILD_TYPE "unknown build type"
#endif

namespace foveart::toolkit {
namespace {

// The value after "key" up to the end of the first line that starts with it in `file`
// (separator ':' or '='), quotes dropped; "" if none.
std::string field_of(const char* file, const std::string& key, char separator) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(key, 0) != 0) continue;
    const auto sep = line.find(separator);
    if (sep == std::string::npos) continue;
    std::string v = line.substr(sep + 1);
    v.erase(0, v.find_first_not_of(" \t\""));
    while (!v.empty() && (v.back() == '"' || v.back() == ' ' || v.back() == '\t')) v.pop_back();
    return v;
  }
  return "";
}

std::string compiler() {
#if defined(__clang__)
  return "Clang " __clang_version__;
#elif defined(__GNUC__)
  return "GCC " __VERSION__;
#else
  return "unknown compiler";
#endif
}

std::string& recorded() {
  static std::string command;
  return command;
}

}  // namespace

std::string machine_description() {
  std::string cpu = field_of("/proc/cpuinfo", "model name", ':');
  if (cpu.empty()) cpu = "unknown CPU";
  std::string os = field_of("/etc/os-release", "PRETTY_NAME", '=');
  if (os.empty()) os = "unknown OS";
  utsname u{};
  if (uname(&u) == 0) os += std::string(", ") + u.sysname + " " + u.release;
  return cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores; " + os + "; " + compiler() + ", " +
         FOVEART_BUILD_TYPE;
}

std::string shell_quote(const std::string& arg) {
  if (!arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                            "-_./:=,+@%") == std::string::npos)
    return arg;
  std::string q = "'";
  for (char c : arg) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

void set_command_line(int argc, const char* const* argv) {
  std::string& c = recorded();
  c.clear();
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    if (i == 0) a = a.substr(a.find_last_of('/') + 1);  // the tool's name, not where it was built
    c += (i ? " " : "") + shell_quote(a);
  }
}

const std::string& command_line() {
  return recorded();
}

std::string result_header(const std::string& command) {
  return "Written by `" + command + "` on " + machine_description() +
         ". The numbers below are that run's own output; rerun the command to update them.\n";
}

}  // namespace foveart::toolkit
