// vk_count_probe: the counting layer's positive control, a plain Vulkan program
// that renders `--frames` frames the pipelined way (two frames in flight: frame
// i waits for frame i-2's fence before reusing its slot, one submission per
// frame) and, on request, adds per frame exactly what a regression would:
//   --wait      a wait on this frame's fence right after submitting it
//   --readback  a full-image read-back of the finished frame i-2: map, invalidate
//               and unmap of its whole width x height x 4-byte buffer
//   --staging   a full-image read-back through a persistent map: each frame also
//               copies its buffer into a staging buffer mapped once at start-up
// Exit 0 when every Vulkan call succeeded; 1 with a message otherwise.
#include <vulkan/vulkan.h>

#include "icd_pin.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Options {
  int frames = 6;
  uint32_t width = 320, height = 360;
  bool wait = false, readback = false, staging = false;
};

[[noreturn]] void die(const char* what, VkResult r) {
  std::fprintf(stderr, "vk_count_probe: %s failed (VkResult %d)\n", what, static_cast<int>(r));
  std::exit(1);
}

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) die(what, r);
}

bool parse(int argc, char** argv, Options* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--wait") {
      o->wait = true;
    } else if (a == "--readback") {
      o->readback = true;
    } else if (a == "--staging") {
      o->staging = true;
    } else if (a == "--frames" && i + 1 < argc) {
      o->frames = std::atoi(argv[++i]);
    } else if (a == "--size" && i + 2 < argc) {
      o->width = static_cast<uint32_t>(std::atoi(argv[++i]));
      o->height = static_cast<uint32_t>(std::atoi(argv[++i]));
    } else {
      return false;
    }
  }
  return o->frames > 0 && o->width > 0 && o->height > 0;
}

struct Device {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkQueue queue = VK_NULL_HANDLE;
};

Device open_device() {
  Device d;
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "vk_count_probe";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  check(vkCreateInstance(&info, nullptr, &d.instance), "vkCreateInstance");
  uint32_t count = 1;
  const VkResult r = vkEnumeratePhysicalDevices(d.instance, &count, &d.physical);
  if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || count == 0) die("vkEnumeratePhysicalDevices", r);
  vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(d.physical, &count, families.data());
  while (d.family < count && (families[d.family].queueFlags & VK_QUEUE_TRANSFER_BIT) == 0 &&
         (families[d.family].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0)
    ++d.family;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue{};
  queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue.queueFamilyIndex = d.family;
  queue.queueCount = 1;
  queue.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue;
  check(vkCreateDevice(d.physical, &device_info, nullptr, &d.device), "vkCreateDevice");
  vkGetDeviceQueue(d.device, d.family, 0, &d.queue);
  return d;
}

// One frame slot: the frame's image as a host-visible buffer, its commands and fence.
struct Slot {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkBuffer staging = VK_NULL_HANDLE;  // --staging: the read-back's, mapped for the probe's life
  VkDeviceMemory staging_memory = VK_NULL_HANDLE;
  void* staging_data = nullptr;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
};

// A host-visible buffer of `bytes` bytes.
void make_buffer(const Device& d, VkDeviceSize bytes, VkBufferUsageFlags usage, VkBuffer* buffer,
                 VkDeviceMemory* memory) {
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = bytes;
  info.usage = usage;
  check(vkCreateBuffer(d.device, &info, nullptr, buffer), "vkCreateBuffer");
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(d.device, *buffer, &req);
  VkPhysicalDeviceMemoryProperties props{};
  vkGetPhysicalDeviceMemoryProperties(d.physical, &props);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = UINT32_MAX;
  for (uint32_t i = 0; i < props.memoryTypeCount && alloc.memoryTypeIndex == UINT32_MAX; ++i)
    if ((req.memoryTypeBits & (1u << i)) != 0 &&
        (props.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0)
      alloc.memoryTypeIndex = i;
  if (alloc.memoryTypeIndex == UINT32_MAX) die("finding host-visible memory", VK_ERROR_FEATURE_NOT_PRESENT);
  check(vkAllocateMemory(d.device, &alloc, nullptr, memory), "vkAllocateMemory");
  check(vkBindBufferMemory(d.device, *buffer, *memory, 0), "vkBindBufferMemory");
}

Slot make_slot(const Device& d, VkCommandPool pool, VkDeviceSize bytes, bool staging) {
  Slot s;
  make_buffer(d, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, &s.buffer, &s.memory);
  if (staging) {
    make_buffer(d, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, &s.staging, &s.staging_memory);
    check(vkMapMemory(d.device, s.staging_memory, 0, VK_WHOLE_SIZE, 0, &s.staging_data), "vkMapMemory (staging)");
  }
  VkCommandBufferAllocateInfo cb_info{};
  cb_info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cb_info.commandPool = pool;
  cb_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cb_info.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(d.device, &cb_info, &s.cb), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fence{};
  fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  check(vkCreateFence(d.device, &fence, nullptr, &s.fence), "vkCreateFence");
  return s;
}

// Frame `frame` into `s`: fill its buffer with the frame number (and make it host-readable), submit.
void render(const Device& d, Slot& s, VkDeviceSize bytes, uint32_t frame) {
  check(vkResetCommandBuffer(s.cb, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(s.cb, &begin), "vkBeginCommandBuffer");
  vkCmdFillBuffer(s.cb, s.buffer, 0, bytes, frame);
  if (s.staging != VK_NULL_HANDLE) {
    VkMemoryBarrier filled{};
    filled.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    filled.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    filled.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    vkCmdPipelineBarrier(s.cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &filled, 0,
                         nullptr, 0, nullptr);
    const VkBufferCopy copy{0, 0, bytes};
    vkCmdCopyBuffer(s.cb, s.buffer, s.staging, 1, &copy);
  }
  VkMemoryBarrier to_host{};
  to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(s.cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0,
                       nullptr);
  check(vkEndCommandBuffer(s.cb), "vkEndCommandBuffer");
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &s.cb;
  check(vkQueueSubmit(d.queue, 1, &submit, s.fence), "vkQueueSubmit");
}

// The read-back of a finished frame: map, invalidate, check its first word, unmap.
void read_back(const Device& d, const Slot& s, uint32_t frame) {
  void* data = nullptr;
  check(vkMapMemory(d.device, s.memory, 0, VK_WHOLE_SIZE, 0, &data), "vkMapMemory");
  VkMappedMemoryRange range{};
  range.sType = VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE;
  range.memory = s.memory;
  range.size = VK_WHOLE_SIZE;
  check(vkInvalidateMappedMemoryRanges(d.device, 1, &range), "vkInvalidateMappedMemoryRanges");
  uint32_t first = 0;
  std::memcpy(&first, data, sizeof first);
  vkUnmapMemory(d.device, s.memory);
  if (first != frame) die("reading back the frame (wrong contents)", VK_ERROR_UNKNOWN);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, &o)) {
    std::fprintf(stderr, "usage: vk_count_probe [--frames N] [--size W H] [--wait] [--readback] [--staging]\n");
    return 2;
  }
  Device d = open_device();
  foveart::sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
  VkCommandPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = d.family;
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(d.device, &pool_info, nullptr, &pool), "vkCreateCommandPool");
  const VkDeviceSize bytes = VkDeviceSize{o.width} * o.height * 4;
  Slot slots[2] = {make_slot(d, pool, bytes, o.staging), make_slot(d, pool, bytes, o.staging)};
  for (int i = 0; i < o.frames; ++i) {
    Slot& s = slots[i % 2];
    if (i >= 2) {  // the slot's previous frame, i - 2, is an older frame still in flight
      check(vkWaitForFences(d.device, 1, &s.fence, VK_TRUE, UINT64_MAX), "vkWaitForFences (older frame)");
      if (o.readback) read_back(d, s, static_cast<uint32_t>(i - 2));
      uint32_t first = static_cast<uint32_t>(i - 2);
      if (o.staging) std::memcpy(&first, s.staging_data, sizeof first);  // the persistent map: no call to count
      if (first != static_cast<uint32_t>(i - 2)) die("reading the staging buffer (wrong contents)", VK_ERROR_UNKNOWN);
      check(vkResetFences(d.device, 1, &s.fence), "vkResetFences");
    }
    render(d, s, bytes, static_cast<uint32_t>(i));
    if (o.wait) check(vkWaitForFences(d.device, 1, &s.fence, VK_TRUE, UINT64_MAX), "vkWaitForFences (this frame)");
  }
  check(vkDeviceWaitIdle(d.device), "vkDeviceWaitIdle");
  for (Slot& s : slots) {
    vkDestroyFence(d.device, s.fence, nullptr);
    vkDestroyBuffer(d.device, s.buffer, nullptr);
    vkFreeMemory(d.device, s.memory, nullptr);
    if (s.staging != VK_NULL_HANDLE) vkDestroyBuffer(d.device, s.staging, nullptr);
    if (s.staging_memory != VK_NULL_HANDLE) vkFreeMemory(d.device, s.staging_memory, nullptr);  // unmaps
  }
  vkDestroyCommandPool(d.device, pool, nullptr);
  vkDestroyDevice(d.device, nullptr);
  vkDestroyInstance(d.instance, nullptr);
  std::printf("vk_count_probe: %d frames of %ux%u%s%s%s\n", o.frames, o.width, o.height, o.wait ? ", --wait" : "",
              o.readback ? ", --readback" : "", o.staging ? ", --staging" : "");
  return 0;
}
