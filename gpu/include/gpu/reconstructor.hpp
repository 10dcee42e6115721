// The device frame's entry point for one Vulkan device (docs/gpu.md): checks
// that the shaders can run there, makes the context and every pipeline once,
// and hands out table sets (one per view size, shared by the eyes) and eyes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "foveation/foveated_view.hpp"
#include "gpu/context.hpp"
#include "gpu/eye.hpp"
#include "gpu/frame_pipelines.hpp"
#include "gpu/tables.hpp"

namespace foveart::gpu {

// Why the shaders cannot run on `device`: its queue family, features and limits, and the Vulkan
// version the app's instance lets them use; empty when they can.
std::string unsupported_reason(const Device& device);

class Reconstructor {
 public:
  // Null with *error when the device cannot run the shaders (unsupported_reason) or a Vulkan call fails.
  static std::unique_ptr<Reconstructor> create(const Device& device, std::string* error);

  // Packs and uploads `tables` (submits and waits on the device's queue) in
  // buffers of at most max_chunk_bytes (0: the device's maxStorageBufferRange).
  std::shared_ptr<Tables> upload_tables(std::shared_ptr<const foveation::ViewTables> tables, std::string* error,
                                        std::size_t max_chunk_bytes = 0) {
    return Tables::upload(*context_, std::move(tables), max_chunk_bytes, error);
  }
  std::unique_ptr<Eye> create_eye(uint32_t width_px, uint32_t height_px, std::string* error) {
    return Eye::create(*context_, *pipelines_, width_px, height_px, error);
  }
  // Records with `record` into a one-time command buffer, submits it and waits (uploads, tests, benchmarks).
  [[nodiscard]] bool submit_and_wait(const std::function<bool(VkCommandBuffer)>& record, std::string* error) {
    return context_->submit_and_wait(record, error);
  }

  VkDeviceSize max_chunk_bytes() const { return context_->max_storage_buffer_bytes(); }
  const Device& device() const { return context_->device(); }
  Context& context() { return *context_; }

 private:
  Reconstructor() = default;
  std::unique_ptr<Context> context_;
  std::unique_ptr<FramePipelines> pipelines_;  // after context_: destroyed first
};

}  // namespace foveart::gpu
