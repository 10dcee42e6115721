// libFuzzer: the one gaze trace reader (replay, gaze-diag, the simulated runtime).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "gaze_provider/trace_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  foveart::gaze::TraceError error;
  const auto trace = foveart::gaze::read_trace(in, &error);
  if (!trace && error.to_string().empty()) __builtin_trap();
  return 0;
}
