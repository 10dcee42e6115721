// Shared plumbing for the OpenXR entry points: the function table each api_*.cpp
// fills, the exception barrier, and the two-call idiom.
#pragma once

#include <algorithm>
#include <exception>
#include <string>
#include <unordered_map>
#include <vector>

#include "log.h"
#include "state.h"

namespace foveart::sim {

enum class Extension { None, Vulkan, Vulkan2, EyeGaze, Timespec };

struct FunctionEntry {
  PFN_xrVoidFunction fn = nullptr;
  Extension extension = Extension::None;
};
using FunctionTable = std::unordered_map<std::string, FunctionEntry>;

template <class Fn>
void add(FunctionTable& table, const char* name, Fn fn, Extension ext = Extension::None) {
  table[name] = FunctionEntry{reinterpret_cast<PFN_xrVoidFunction>(fn), ext};
}

void register_instance_functions(FunctionTable& table);
void register_vulkan_functions(FunctionTable& table);
void register_session_functions(FunctionTable& table);
void register_space_functions(FunctionTable& table);
void register_swapchain_functions(FunctionTable& table);
void register_action_functions(FunctionTable& table);

// Nothing escapes an entry point: exceptions become XR_ERROR_RUNTIME_FAILURE.
template <class Body>
XrResult guarded(const char* name, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::exception& e) {
    log(LogLevel::Error, std::string(name) + ": " + e.what());
  } catch (...) {
    log(LogLevel::Error, std::string(name) + ": unknown exception");
  }
  return XR_ERROR_RUNTIME_FAILURE;
}

// Locks the runtime and resolves the instance; for entry points taking XrInstance.
#define FOVEART_LOCK_INSTANCE(handle)          \
  Runtime& rt = runtime();                     \
  std::unique_lock<std::mutex> lock(rt.mutex); \
  Instance* inst = find_instance(handle);      \
  if (inst == nullptr) return XR_ERROR_HANDLE_INVALID;

#define FOVEART_LOCK_SESSION(handle)                                      \
  Runtime& rt = runtime();                                                \
  std::unique_lock<std::mutex> lock(rt.mutex);                            \
  Session* session = find(rt.sessions, handle);                           \
  if (session == nullptr || !rt.instance) return XR_ERROR_HANDLE_INVALID; \
  Instance* inst = rt.instance.get();

#define FOVEART_CHECK_STRUCT(ptr, xr_type) \
  if ((ptr) == nullptr || (ptr)->type != (xr_type)) return XR_ERROR_VALIDATION_FAILURE;

// Two-call idiom for plain values.
template <class T>
XrResult two_call(uint32_t capacity, uint32_t* count_out, T* out, const std::vector<T>& items) {
  if (count_out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *count_out = static_cast<uint32_t>(items.size());
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < items.size()) return XR_ERROR_SIZE_INSUFFICIENT;
  if (out == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  std::copy(items.begin(), items.end(), out);
  return XR_SUCCESS;
}

// Two-call idiom for strings (count includes the terminating NUL).
XrResult two_call_string(uint32_t capacity, uint32_t* count_out, char* out, const std::string& s);

// Finds a struct of the given type in a next chain.
template <class T>
T* find_in_chain(void* next, XrStructureType type) {
  auto* base = static_cast<XrBaseOutStructure*>(next);
  while (base != nullptr) {
    if (base->type == type) return reinterpret_cast<T*>(base);
    base = base->next;
  }
  return nullptr;
}
template <class T>
const T* find_in_chain(const void* next, XrStructureType type) {
  auto* base = static_cast<const XrBaseInStructure*>(next);
  while (base != nullptr) {
    if (base->type == type) return reinterpret_cast<const T*>(base);
    base = base->next;
  }
  return nullptr;
}

// Valid action/action-set names: lower-case letters, digits, '-', '_', '.'.
bool is_well_formed_name(const char* name, size_t max_size);

}  // namespace foveart::sim
