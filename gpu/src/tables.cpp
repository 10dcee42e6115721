#include "gpu/tables.hpp"

#include <algorithm>
#include <cstring>

namespace foveart::gpu {

std::shared_ptr<Tables> Tables::upload(Context& context, std::shared_ptr<const foveation::ViewTables> tables,
                                       std::size_t max_chunk_bytes, std::string* error) {
  std::shared_ptr<Tables> g(new Tables());
  g->device_ = context.vk_device();
  g->tables_ = std::move(tables);
  const auto limit = std::size_t(context.max_storage_buffer_bytes());
  if (!pack_tables(*g->tables_, max_chunk_bytes > 0 ? std::min(max_chunk_bytes, limit) : limit, &g->pack_, error)) {
    return nullptr;
  }
  for (TableChunk& chunk : g->pack_.chunks) {
    if (!g->upload_chunk(context, chunk, error)) return nullptr;
  }
  return g;
}

bool Tables::upload_chunk(Context& context, TableChunk& chunk, std::string* error) {
  const VkDeviceSize bytes = chunk.words.size() * 4;
  BoundBuffer buffer, staging;
  bool ok = context.create_buffer(&buffer, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  false, error);
  buffers_.push_back(buffer.buffer);
  memory_.push_back(buffer.memory);
  // Through a staging buffer: device-local memory need not be host-visible (discrete GPUs).
  ok = ok && context.create_buffer(&staging, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true, error);
  if (ok) {
    std::memcpy(staging.mapped, chunk.words.data(), bytes);
    ok = context.submit_and_wait(
        [&](VkCommandBuffer cb) {
          const VkBufferCopy copy{0, 0, bytes};
          vkCmdCopyBuffer(cb, staging.buffer, buffer.buffer, 1, &copy);
          memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, kCompute,
                         VK_ACCESS_SHADER_READ_BIT);
          return true;
        },
        error);
  }
  destroy_buffer(device_, &staging);
  if (!ok) return false;
  bytes_ += bytes;
  chunk.words = {};  // on the device now
  return true;
}

Tables::~Tables() {
  for (VkBuffer b : buffers_)
    if (b != VK_NULL_HANDLE) vkDestroyBuffer(device_, b, nullptr);
  for (VkDeviceMemory m : memory_)
    if (m != VK_NULL_HANDLE) vkFreeMemory(device_, m, nullptr);
}

}  // namespace foveart::gpu
