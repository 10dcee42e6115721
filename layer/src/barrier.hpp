// The exception barrier every hook runs behind: nothing crosses the C ABI as an
// exception; a throw becomes XR_ERROR_RUNTIME_FAILURE and one log line.
#pragma once

#include <exception>
#include <new>

#include <openxr/openxr.h>

#include "log.hpp"

namespace foveart::layer {

template <class Body>
XrResult exception_barrier(const char* function_name, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::exception& e) {
    try {
      log(LogLevel::Error, function_name, ": internal error: ", e.what());
    } catch (...) {
    }
  } catch (...) {
    try {
      log(LogLevel::Error, function_name, ": internal error: unknown exception");
    } catch (...) {
    }
  }
  return XR_ERROR_RUNTIME_FAILURE;
}

}  // namespace foveart::layer
