// One view's foveation tables on the device (table_pack.hpp's chunks in
// device-local buffers), shared by both eyes of the view size. Uploaded once
// per foveation::ViewTables through a staging buffer.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "foveation/foveated_view.hpp"
#include "gpu/context.hpp"
#include "gpu/table_pack.hpp"

namespace foveart::gpu {

class Tables {
 public:
  // Packs `tables` in buffers of at most max_chunk_bytes (0: the device's
  // maxStorageBufferRange) and uploads them (submits and waits on the context's
  // queue); null with *error when they cannot be packed or a Vulkan call fails.
  static std::shared_ptr<Tables> upload(Context& context, std::shared_ptr<const foveation::ViewTables> tables,
                                        std::size_t max_chunk_bytes, std::string* error);
  ~Tables();
  Tables(const Tables&) = delete;
  Tables& operator=(const Tables&) = delete;

  const TablePack& layout() const { return pack_; }  // chunk words are dropped after upload
  const foveation::ViewTables& view_tables() const { return *tables_; }
  std::span<const VkBuffer> buffers() const { return buffers_; }  // one per chunk
  std::size_t bytes() const { return bytes_; }

 private:
  Tables() = default;
  [[nodiscard]] bool upload_chunk(Context& context, TableChunk& chunk, std::string* error);

  VkDevice device_ = VK_NULL_HANDLE;
  std::shared_ptr<const foveation::ViewTables> tables_;
  TablePack pack_;
  std::vector<VkBuffer> buffers_;
  std::vector<VkDeviceMemory> memory_;
  std::size_t bytes_ = 0;
};

}  // namespace foveart::gpu
