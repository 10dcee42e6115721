// The GPU engine's memory: where each buffer and image lives and how it is filled.
//   MappedBuffer:  host-visible, coherent, mapped for its whole life (device-local
//                  too where the device offers such a type): what the host reads
//                  or writes after creation (ray counters, staging, the ray-tracing
//                  backend's shader binding table).
//   DeviceBuffer:  device-local where the device allows (MemoryLedger), filled
//                  once through staging (Uploader); host-visible and mapped when
//                  device-local memory is unavailable, the reason kept once.
//   MemoryLedger:  the allocations' bytes by kind and the fallback's one line.
// With VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT in `usage` memory is allocated
// with VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT (the ray-tracing backend's buffers).
#pragma once

#include <vulkan/vulkan.h>

#include <gpu_engine/gpu_tracer.hpp>  // MemoryUse

#include "command_slot.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace foveart::gpu_engine {


class MemoryLedger {
 public:
  // device_local_allowed false: behave as if the device had no device-local memory (tests).
  MemoryLedger(VkPhysicalDevice physical_device, VkDevice device, bool device_local_allowed);
  VkDevice device() const { return device_; }
  VkPhysicalDevice physical_device() const { return physical_; }

  struct Allocation {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize bytes = 0;
    bool device_local = false;
    bool host_visible = false;  // mappable
    bool texture = false;
  };
  // Device-local memory for `req` where allowed and possible, else host-visible
  // coherent memory (the first such fallback's reason kept in fallback()).
  [[nodiscard]] bool allocate(const VkMemoryRequirements& req, bool device_address, bool texture, Allocation* out,
                              std::string* error);
  void release(Allocation* a);

  const MemoryUse& use() const { return use_; }
  const std::string& fallback() const { return fallback_; }  // empty: everything got device-local memory
  void note_fallback(const std::string& why);                 // keeps the first reason only

 private:
  VkPhysicalDevice physical_;
  VkDevice device_;
  bool device_local_allowed_;
  VkPhysicalDeviceMemoryProperties props_{};
  MemoryUse use_;
  std::string fallback_;
};

class MappedBuffer {
 public:
  MappedBuffer() = default;
  ~MappedBuffer() { destroy(); }
  MappedBuffer(const MappedBuffer&) = delete;
  MappedBuffer& operator=(const MappedBuffer&) = delete;

  // A buffer of max(bytes, 16) bytes; `data` (bytes long, may be null) copied in.
  [[nodiscard]] bool create(VkPhysicalDevice physical_device, VkDevice device, VkDeviceSize bytes, const void* data,
              std::string* error, VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  void destroy();

  VkBuffer buffer() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  ~DeviceBuffer() { destroy(); }
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  // max(bytes, 16) bytes, zeroed only when mapped (fill it with an Uploader);
  // TRANSFER_DST is added to `usage`.
  [[nodiscard]] bool create(const std::shared_ptr<MemoryLedger>& ledger, VkDeviceSize bytes, VkBufferUsageFlags usage,
                            std::string* error);
  void destroy();

  VkBuffer buffer() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  void* mapped() const { return mapped_; }  // non-null: the host-visible fallback
  bool device_local() const { return allocation_.device_local; }

 private:
  std::shared_ptr<MemoryLedger> ledger_;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  MemoryLedger::Allocation allocation_;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
};

// Fills DeviceBuffers and images through host-visible staging buffers and
// copies in one-time command buffers on `queue`, each submission waited for and
// its staging released (every kFlushBytes of staging, and at finish()). After
// the last submission a barrier makes the copies visible to every later
// command on the queue (shader reads, acceleration structure builds).
class Uploader {
 public:
  Uploader(VkPhysicalDevice physical_device, VkDevice device, uint32_t queue_family, VkQueue queue);
  Uploader(const Uploader&) = delete;
  Uploader& operator=(const Uploader&) = delete;

  [[nodiscard]] bool buffer(const DeviceBuffer& dst, const void* data, VkDeviceSize bytes, std::string* error);
  // Mip level `level` (width x height) of an image of one layer, `texel_bytes` per texel, tightly
  // packed: UNDEFINED -> TRANSFER_DST_OPTIMAL -> copy -> SHADER_READ_ONLY_OPTIMAL, that level alone.
  [[nodiscard]] bool image(VkImage dst, uint32_t width, uint32_t height, uint32_t texel_bytes, const void* data,
                           std::string* error, uint32_t level = 0);
  [[nodiscard]] bool finish(std::string* error);  // records nothing more afterwards

  static constexpr VkDeviceSize kFlushBytes = VkDeviceSize{64} << 20;

 private:
  bool begin(std::string* error);
  bool submit(std::string* error);
  MappedBuffer* stage(const void* data, VkDeviceSize bytes, std::string* error);

  VkPhysicalDevice physical_;
  VkDevice device_;
  uint32_t family_;
  VkQueue queue_;
  CommandSlot commands_;
  bool recording_ = false;
  VkDeviceSize staged_bytes_ = 0;
  std::vector<std::unique_ptr<MappedBuffer>> staging_;
};

}  // namespace foveart::gpu_engine
