// VK_LAYER_FOVEART_count: a test-only Vulkan layer that counts, per device, the
// host's transfers and waits at the Vulkan boundary, whoever makes them:
// submissions (calls, batches, command buffers), fence waits (split by whether
// a fence's submission is the newest on its queue: a wait on this frame's work,
// or on an older frame still in flight, or on a fence never submitted), queue
// and device idle waits, semaphore waits, query results with and without
// VK_QUERY_RESULT_WAIT_BIT, fence status polls, maps (and bytes), unmaps,
// flushes and invalidations (and bytes), and the transfers through memory the
// host keeps mapped: a submitted vkCmdCopyBuffer / vkCmdCopyImageToBuffer into a
// buffer whose memory was mapped when it was recorded is a copy to the host
// (a read-back through a persistent map), one out of such a buffer
// (vkCmdCopyBuffer, vkCmdCopyBufferToImage) a copy from the host; bytes for
// buffer copies, texels for image copies. And the work a submission carries:
// the dispatches (direct, indirect), pipeline barriers and ray-tracing launches
// recorded into its command buffers (secondary command buffers not looked into).
//
// Each call is an event with its thread and its caller: the modules on the
// stack (shared objects and the program, by file name, innermost first, this
// layer and the Vulkan loader left out), so a test can tell the app's calls
// from the OpenXR layer's and the runtime's, and split frames at the app's own
// submissions. At vkDestroyDevice (and, for devices never destroyed, when the
// layer is unloaded) the device's record is appended as one JSON line to the
// file FOVEART_VK_COUNT_OUT names (nothing is written without it).
//
// The loader-layer interface (vk_layer.h): vkNegotiateLoaderLayerInterfaceVersion,
// the next link taken from VkLayer{Instance,Device}CreateInfo, dispatch data
// by dispatchable handle (a queue or command buffer shares its device's key).
// Enabled with VK_LAYER_PATH=<this build's vk_count/layer> and
// VK_INSTANCE_LAYERS=VK_LAYER_FOVEART_count.
#include <vulkan/vk_layer.h>
#include <vulkan/vulkan.h>

#include <dlfcn.h>
#include <execinfo.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace {

using Key = void*;
template <class Handle>
Key key_of(Handle h) {
  return *reinterpret_cast<Key*>(h);  // the loader's dispatch pointer, shared by a device's queues
}

struct InstanceData {
  VkInstance instance = VK_NULL_HANDLE;
  PFN_vkGetInstanceProcAddr gipa = nullptr;
  PFN_vkDestroyInstance destroy = nullptr;
};

// One intercepted call.
struct Event {
  uint64_t seq = 0;
  long thread = 0;
  const char* call = "";
  const char* kind = "";  // what of the call is counted ("" for a plain count)
  uint64_t items = 0;     // fences waited, batches submitted, ranges, queries
  uint64_t bytes = 0;
  uint64_t command_buffers = 0;  // a submission's
  uint64_t texels = 0;           // a copy event's, of image copies
  // A submission's number on its device (from 1); a fence wait's: the newest
  // submission its fences signal (0: none submitted).
  uint64_t submission = 0;
  std::vector<std::string> chain;  // callers, innermost first
};

// The copies through mapped memory a command buffer holds, since its vkBeginCommandBuffer.
struct Copies {
  uint64_t to_host = 0, to_host_bytes = 0, to_host_texels = 0;
  uint64_t from_host = 0, from_host_bytes = 0, from_host_texels = 0;
};

// The commands of work a command buffer holds, since its vkBeginCommandBuffer.
struct Commands {
  uint64_t dispatches = 0, dispatches_indirect = 0, barriers = 0, trace_rays = 0;
};

struct DeviceData {
  VkDevice device = VK_NULL_HANDLE;
  std::string name;
  PFN_vkGetDeviceProcAddr gdpa = nullptr;
  PFN_vkDestroyDevice DestroyDevice = nullptr;
  PFN_vkQueueSubmit QueueSubmit = nullptr;
  PFN_vkQueueSubmit2 QueueSubmit2 = nullptr;
  PFN_vkQueueSubmit2 QueueSubmit2KHR = nullptr;
  PFN_vkWaitForFences WaitForFences = nullptr;
  PFN_vkResetFences ResetFences = nullptr;
  PFN_vkDestroyFence DestroyFence = nullptr;
  PFN_vkGetFenceStatus GetFenceStatus = nullptr;
  PFN_vkQueueWaitIdle QueueWaitIdle = nullptr;
  PFN_vkDeviceWaitIdle DeviceWaitIdle = nullptr;
  PFN_vkWaitSemaphores WaitSemaphores = nullptr;
  PFN_vkWaitSemaphores WaitSemaphoresKHR = nullptr;
  PFN_vkGetQueryPoolResults GetQueryPoolResults = nullptr;
  PFN_vkAllocateMemory AllocateMemory = nullptr;
  PFN_vkFreeMemory FreeMemory = nullptr;
  PFN_vkMapMemory MapMemory = nullptr;
  PFN_vkUnmapMemory UnmapMemory = nullptr;
  PFN_vkFlushMappedMemoryRanges FlushMappedMemoryRanges = nullptr;
  PFN_vkInvalidateMappedMemoryRanges InvalidateMappedMemoryRanges = nullptr;
  PFN_vkBindBufferMemory BindBufferMemory = nullptr;
  PFN_vkBindBufferMemory2 BindBufferMemory2 = nullptr;
  PFN_vkBindBufferMemory2 BindBufferMemory2KHR = nullptr;
  PFN_vkBeginCommandBuffer BeginCommandBuffer = nullptr;
  PFN_vkCmdCopyBuffer CmdCopyBuffer = nullptr;
  PFN_vkCmdCopyImageToBuffer CmdCopyImageToBuffer = nullptr;
  PFN_vkCmdCopyBufferToImage CmdCopyBufferToImage = nullptr;
  PFN_vkCmdDispatch CmdDispatch = nullptr;
  PFN_vkCmdDispatchIndirect CmdDispatchIndirect = nullptr;
  PFN_vkCmdPipelineBarrier CmdPipelineBarrier = nullptr;
  PFN_vkCmdPipelineBarrier2 CmdPipelineBarrier2 = nullptr;
  PFN_vkCmdPipelineBarrier2 CmdPipelineBarrier2KHR = nullptr;
  PFN_vkCmdTraceRaysKHR CmdTraceRaysKHR = nullptr;
  PFN_vkCmdTraceRaysIndirectKHR CmdTraceRaysIndirectKHR = nullptr;

  // Guarded by the layer's mutex.
  uint64_t submissions = 0;                                   // every submission on every queue, numbered
  std::unordered_map<VkQueue, uint64_t> newest;               // a queue's newest submission
  std::unordered_map<VkFence, std::pair<VkQueue, uint64_t>> fence_submission;  // a fence's pending one
  std::unordered_map<VkDeviceMemory, VkDeviceSize> memory_size;
  std::unordered_set<VkDeviceMemory> mapped;                  // mapped now
  std::unordered_map<VkBuffer, VkDeviceMemory> buffer_memory;  // as bound
  std::unordered_map<VkCommandBuffer, Copies> recorded;
  std::unordered_map<VkCommandBuffer, Commands> commands;
  std::vector<Event> events;
};

// The layer's state: the per-instance and per-device maps, by dispatch key.
struct Layer {
  std::mutex mutex;
  std::unordered_map<Key, InstanceData> instances;
  std::unordered_map<Key, DeviceData> devices;
  ~Layer();
};

Layer& layer() {
  static Layer l;
  return l;
}

// ---- callers -----------------------------------------------------------------

std::string module_of(void* address) {
  Dl_info info{};
  if (dladdr(address, &info) == 0 || info.dli_fname == nullptr) return "?";
  const char* slash = std::strrchr(info.dli_fname, '/');
  return slash != nullptr ? slash + 1 : info.dli_fname;
}

// The modules on the calling thread's stack, innermost first, without this layer
// and the Vulkan loader; consecutive frames of one module once.
std::vector<std::string> caller_chain() {
  void* frames[64];
  const int n = backtrace(frames, 64);
  static const std::string self = module_of(reinterpret_cast<void*>(&module_of));
  std::vector<std::string> chain;
  for (int i = 1; i < n; ++i) {
    std::string m = module_of(frames[i]);
    if (m == self || m.rfind("libvulkan.so", 0) == 0) continue;
    if (chain.empty() || chain.back() != m) chain.push_back(std::move(m));
  }
  return chain;
}

long thread_id() { return static_cast<long>(syscall(SYS_gettid)); }

// Records one event on `d`; the caller holds the mutex.
void record(DeviceData& d, const char* call, const char* kind, uint64_t items, uint64_t bytes,
            std::vector<std::string> chain) {
  Event e;
  e.seq = d.events.size();
  e.thread = thread_id();
  e.call = call;
  e.kind = kind;
  e.items = items;
  e.bytes = bytes;
  e.chain = std::move(chain);
  d.events.push_back(std::move(e));
}

// Looks up the device of a dispatchable handle and records an event (chain taken
// before the lock: backtrace may be slow).
template <class Handle>
DeviceData* record_on(Handle h, const char* call, const char* kind, uint64_t items, uint64_t bytes) {
  auto chain = caller_chain();
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  auto it = l.devices.find(key_of(h));
  if (it == l.devices.end()) return nullptr;
  record(it->second, call, kind, items, bytes, std::move(chain));
  return &it->second;
}

DeviceData& device_of(Key k) {
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  return l.devices.at(k);  // the entry lives until vkDestroyDevice; its function pointers never change
}

// ---- output -------------------------------------------------------------------

nlohmann::json to_json(const DeviceData& d) {
  struct Tally {
    uint64_t calls = 0, items = 0, bytes = 0, command_buffers = 0, texels = 0;
  };
  std::map<std::string, Tally> tallies;
  nlohmann::json events = nlohmann::json::array();
  for (const Event& e : d.events) {
    Tally& t = tallies[*e.kind != '\0' ? std::string(e.call) + "." + e.kind : std::string(e.call)];
    t.calls += 1;
    t.items += e.items;
    t.bytes += e.bytes;
    t.command_buffers += e.command_buffers;
    t.texels += e.texels;
    events.push_back({{"seq", e.seq}, {"thread", e.thread}, {"call", e.call}, {"kind", e.kind}, {"items", e.items},
                      {"bytes", e.bytes}, {"command_buffers", e.command_buffers}, {"texels", e.texels},
                      {"submission", e.submission},
                      {"chain", e.chain}});
  }
  nlohmann::json totals = nlohmann::json::object();
  for (const auto& [metric, t] : tallies)
    totals[metric] = {{"calls", t.calls},
                      {"items", t.items},
                      {"bytes", t.bytes},
                      {"command_buffers", t.command_buffers},
                      {"texels", t.texels}};
  return {{"device", d.name}, {"pid", static_cast<long>(getpid())}, {"totals", totals}, {"events", events}};
}

// Appends the device's record to $FOVEART_VK_COUNT_OUT; the caller holds the mutex.
void write_out(const DeviceData& d) {
  const char* path = std::getenv("FOVEART_VK_COUNT_OUT");
  if (path == nullptr || *path == '\0') return;
  std::ofstream(path, std::ios::app) << to_json(d).dump() << '\n';
}

Layer::~Layer() {
  std::lock_guard lock(mutex);
  for (const auto& [k, d] : devices) write_out(d);
  devices.clear();
}

// ---- byte counts ---------------------------------------------------------------

VkDeviceSize range_bytes(const DeviceData& d, VkDeviceMemory memory, VkDeviceSize offset, VkDeviceSize size) {
  if (size != VK_WHOLE_SIZE) return size;
  auto it = d.memory_size.find(memory);
  return it != d.memory_size.end() && it->second > offset ? it->second - offset : 0;
}

uint64_t ranges_bytes(const DeviceData& d, uint32_t count, const VkMappedMemoryRange* ranges) {
  uint64_t bytes = 0;
  for (uint32_t i = 0; i < count; ++i) bytes += range_bytes(d, ranges[i].memory, ranges[i].offset, ranges[i].size);
  return bytes;
}

// ---- device functions ----------------------------------------------------------

// The copies through mapped memory that submitting `cbs` performs, as two events
// after the submission's ("copy_to_host", "copy_from_host"; items: copies).
void note_copies(DeviceData& d, const std::vector<VkCommandBuffer>& cbs, const std::vector<std::string>& chain) {
  Copies sum;
  for (VkCommandBuffer cb : cbs) {
    auto it = d.recorded.find(cb);
    if (it == d.recorded.end()) continue;
    const Copies& c = it->second;
    sum.to_host += c.to_host;
    sum.to_host_bytes += c.to_host_bytes;
    sum.to_host_texels += c.to_host_texels;
    sum.from_host += c.from_host;
    sum.from_host_bytes += c.from_host_bytes;
    sum.from_host_texels += c.from_host_texels;
  }
  if (sum.to_host > 0) {
    record(d, "copy_to_host", "", sum.to_host, sum.to_host_bytes, chain);
    d.events.back().texels = sum.to_host_texels;
  }
  if (sum.from_host > 0) {
    record(d, "copy_from_host", "", sum.from_host, sum.from_host_bytes, chain);
    d.events.back().texels = sum.from_host_texels;
  }
}

// The work that submitting `cbs` carries, as one event per kind after the
// submission's (named by the command; items: how many were recorded).
void note_commands(DeviceData& d, const std::vector<VkCommandBuffer>& cbs, const std::vector<std::string>& chain) {
  Commands sum;
  for (VkCommandBuffer cb : cbs) {
    auto it = d.commands.find(cb);
    if (it == d.commands.end()) continue;
    sum.dispatches += it->second.dispatches;
    sum.dispatches_indirect += it->second.dispatches_indirect;
    sum.barriers += it->second.barriers;
    sum.trace_rays += it->second.trace_rays;
  }
  const std::pair<const char*, uint64_t> kinds[] = {{"vkCmdDispatch", sum.dispatches},
                                                    {"vkCmdDispatchIndirect", sum.dispatches_indirect},
                                                    {"vkCmdPipelineBarrier", sum.barriers},
                                                    {"vkCmdTraceRaysKHR", sum.trace_rays}};
  for (const auto& [call, items] : kinds)
    if (items > 0) record(d, call, "", items, 0, chain);
}

// A submission of `batches` batches with command buffers `cbs` to `queue`, signalling `fence`.
void note_submission(VkQueue queue, const char* call, uint64_t batches, const std::vector<VkCommandBuffer>& cbs,
                     VkFence fence) {
  auto chain = caller_chain();
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  auto it = l.devices.find(key_of(queue));
  if (it == l.devices.end()) return;
  DeviceData& d = it->second;
  const uint64_t number = ++d.submissions;
  d.newest[queue] = number;
  if (fence != VK_NULL_HANDLE) d.fence_submission[fence] = {queue, number};
  record(d, call, "", batches, 0, chain);
  d.events.back().command_buffers = cbs.size();
  d.events.back().submission = number;
  note_copies(d, cbs, chain);
  note_commands(d, cbs, chain);
}

VKAPI_ATTR VkResult VKAPI_CALL QueueSubmit(VkQueue queue, uint32_t count, const VkSubmitInfo* submits, VkFence fence) {
  std::vector<VkCommandBuffer> cbs;
  for (uint32_t i = 0; i < count; ++i)
    cbs.insert(cbs.end(), submits[i].pCommandBuffers, submits[i].pCommandBuffers + submits[i].commandBufferCount);
  note_submission(queue, "vkQueueSubmit", count, cbs, fence);
  return device_of(key_of(queue)).QueueSubmit(queue, count, submits, fence);
}

std::vector<VkCommandBuffer> command_buffers2(uint32_t count, const VkSubmitInfo2* submits) {
  std::vector<VkCommandBuffer> cbs;
  for (uint32_t i = 0; i < count; ++i)
    for (uint32_t j = 0; j < submits[i].commandBufferInfoCount; ++j)
      cbs.push_back(submits[i].pCommandBufferInfos[j].commandBuffer);
  return cbs;
}

VKAPI_ATTR VkResult VKAPI_CALL QueueSubmit2(VkQueue queue, uint32_t count, const VkSubmitInfo2* submits,
                                            VkFence fence) {
  note_submission(queue, "vkQueueSubmit2", count, command_buffers2(count, submits), fence);
  return device_of(key_of(queue)).QueueSubmit2(queue, count, submits, fence);
}

VKAPI_ATTR VkResult VKAPI_CALL QueueSubmit2KHR(VkQueue queue, uint32_t count, const VkSubmitInfo2* submits,
                                               VkFence fence) {
  note_submission(queue, "vkQueueSubmit2", count, command_buffers2(count, submits), fence);
  return device_of(key_of(queue)).QueueSubmit2KHR(queue, count, submits, fence);
}

// Which frame's work a wait on these fences waits for: "this_frame" when one of
// them signals the newest submission on its queue, else "older_frame" when one
// signals an earlier submission, else "unsubmitted" (never submitted, or reset).
// *submission: the newest submission they signal (0: none).
const char* fence_kind(const DeviceData& d, uint32_t count, const VkFence* fences, uint64_t* submission) {
  bool submitted = false, this_frame = false;
  *submission = 0;
  for (uint32_t i = 0; i < count; ++i) {
    auto it = d.fence_submission.find(fences[i]);
    if (it == d.fence_submission.end()) continue;
    submitted = true;
    *submission = std::max(*submission, it->second.second);
    auto newest = d.newest.find(it->second.first);
    this_frame = this_frame || (newest != d.newest.end() && newest->second == it->second.second);
  }
  return this_frame ? "this_frame" : submitted ? "older_frame" : "unsubmitted";
}

VKAPI_ATTR VkResult VKAPI_CALL WaitForFences(VkDevice device, uint32_t count, const VkFence* fences, VkBool32 all,
                                             uint64_t timeout) {
  auto chain = caller_chain();
  PFN_vkWaitForFences next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    uint64_t submission = 0;
    record(d, "vkWaitForFences", fence_kind(d, count, fences, &submission), count, 0, std::move(chain));
    d.events.back().submission = submission;
    next = d.WaitForFences;
  }
  return next(device, count, fences, all, timeout);  // not under the lock: it blocks
}

VKAPI_ATTR VkResult VKAPI_CALL GetFenceStatus(VkDevice device, VkFence fence) {
  auto chain = caller_chain();
  PFN_vkGetFenceStatus next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    uint64_t submission = 0;
    record(d, "vkGetFenceStatus", fence_kind(d, 1, &fence, &submission), 1, 0, std::move(chain));
    next = d.GetFenceStatus;
  }
  return next(device, fence);
}

VKAPI_ATTR VkResult VKAPI_CALL ResetFences(VkDevice device, uint32_t count, const VkFence* fences) {
  PFN_vkResetFences next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    for (uint32_t i = 0; i < count; ++i) d.fence_submission.erase(fences[i]);
    next = d.ResetFences;
  }
  return next(device, count, fences);
}

VKAPI_ATTR void VKAPI_CALL DestroyFence(VkDevice device, VkFence fence, const VkAllocationCallbacks* allocator) {
  PFN_vkDestroyFence next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    d.fence_submission.erase(fence);
    next = d.DestroyFence;
  }
  next(device, fence, allocator);
}

VKAPI_ATTR VkResult VKAPI_CALL QueueWaitIdle(VkQueue queue) {
  record_on(queue, "vkQueueWaitIdle", "", 1, 0);
  return device_of(key_of(queue)).QueueWaitIdle(queue);
}

VKAPI_ATTR VkResult VKAPI_CALL DeviceWaitIdle(VkDevice device) {
  record_on(device, "vkDeviceWaitIdle", "", 1, 0);
  return device_of(key_of(device)).DeviceWaitIdle(device);
}

VKAPI_ATTR VkResult VKAPI_CALL WaitSemaphores(VkDevice device, const VkSemaphoreWaitInfo* info, uint64_t timeout) {
  record_on(device, "vkWaitSemaphores", "", info->semaphoreCount, 0);
  return device_of(key_of(device)).WaitSemaphores(device, info, timeout);
}

VKAPI_ATTR VkResult VKAPI_CALL WaitSemaphoresKHR(VkDevice device, const VkSemaphoreWaitInfo* info, uint64_t timeout) {
  record_on(device, "vkWaitSemaphores", "", info->semaphoreCount, 0);
  return device_of(key_of(device)).WaitSemaphoresKHR(device, info, timeout);
}

VKAPI_ATTR VkResult VKAPI_CALL GetQueryPoolResults(VkDevice device, VkQueryPool pool, uint32_t first, uint32_t count,
                                                   size_t size, void* data, VkDeviceSize stride,
                                                   VkQueryResultFlags flags) {
  record_on(device, "vkGetQueryPoolResults", (flags & VK_QUERY_RESULT_WAIT_BIT) != 0 ? "wait" : "no_wait", count, size);
  return device_of(key_of(device)).GetQueryPoolResults(device, pool, first, count, size, data, stride, flags);
}

VKAPI_ATTR VkResult VKAPI_CALL AllocateMemory(VkDevice device, const VkMemoryAllocateInfo* info,
                                              const VkAllocationCallbacks* allocator, VkDeviceMemory* memory) {
  const VkResult r = device_of(key_of(device)).AllocateMemory(device, info, allocator, memory);
  if (r == VK_SUCCESS) {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    l.devices.at(key_of(device)).memory_size[*memory] = info->allocationSize;
  }
  return r;
}

VKAPI_ATTR void VKAPI_CALL FreeMemory(VkDevice device, VkDeviceMemory memory, const VkAllocationCallbacks* allocator) {
  PFN_vkFreeMemory next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    d.memory_size.erase(memory);
    d.mapped.erase(memory);  // freeing unmaps
    next = d.FreeMemory;
  }
  next(device, memory, allocator);
}

VKAPI_ATTR VkResult VKAPI_CALL MapMemory(VkDevice device, VkDeviceMemory memory, VkDeviceSize offset, VkDeviceSize size,
                                         VkMemoryMapFlags flags, void** data) {
  auto chain = caller_chain();
  PFN_vkMapMemory next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    record(d, "vkMapMemory", "", 1, range_bytes(d, memory, offset, size), std::move(chain));
    next = d.MapMemory;
  }
  const VkResult r = next(device, memory, offset, size, flags, data);
  if (r == VK_SUCCESS) {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    l.devices.at(key_of(device)).mapped.insert(memory);
  }
  return r;
}

VKAPI_ATTR void VKAPI_CALL UnmapMemory(VkDevice device, VkDeviceMemory memory) {
  if (DeviceData* d = record_on(device, "vkUnmapMemory", "", 1, 0)) {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    d->mapped.erase(memory);
  }
  device_of(key_of(device)).UnmapMemory(device, memory);
}

// ---- copies through mapped memory ------------------------------------------------

VKAPI_ATTR VkResult VKAPI_CALL BindBufferMemory(VkDevice device, VkBuffer buffer, VkDeviceMemory memory,
                                                VkDeviceSize offset) {
  PFN_vkBindBufferMemory next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    d.buffer_memory[buffer] = memory;
    next = d.BindBufferMemory;
  }
  return next(device, buffer, memory, offset);
}

template <PFN_vkBindBufferMemory2 DeviceData::*Next>
VkResult bind_buffer_memory2(VkDevice device, uint32_t count, const VkBindBufferMemoryInfo* infos) {
  PFN_vkBindBufferMemory2 next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    for (uint32_t i = 0; i < count; ++i) d.buffer_memory[infos[i].buffer] = infos[i].memory;
    next = d.*Next;
  }
  return next(device, count, infos);
}

VKAPI_ATTR VkResult VKAPI_CALL BindBufferMemory2(VkDevice device, uint32_t count, const VkBindBufferMemoryInfo* infos) {
  return bind_buffer_memory2<&DeviceData::BindBufferMemory2>(device, count, infos);
}

VKAPI_ATTR VkResult VKAPI_CALL BindBufferMemory2KHR(VkDevice device, uint32_t count,
                                                    const VkBindBufferMemoryInfo* infos) {
  return bind_buffer_memory2<&DeviceData::BindBufferMemory2KHR>(device, count, infos);
}

VKAPI_ATTR VkResult VKAPI_CALL BeginCommandBuffer(VkCommandBuffer cb, const VkCommandBufferBeginInfo* info) {
  PFN_vkBeginCommandBuffer next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(cb));
    d.recorded.erase(cb);  // a begin resets what the buffer held
    d.commands.erase(cb);
    next = d.BeginCommandBuffer;
  }
  return next(cb, info);
}

// Whether `buffer`'s memory is mapped now; the caller holds the mutex.
bool mapped_now(const DeviceData& d, VkBuffer buffer) {
  auto it = d.buffer_memory.find(buffer);
  return it != d.buffer_memory.end() && d.mapped.count(it->second) != 0;
}

VKAPI_ATTR void VKAPI_CALL CmdCopyBuffer(VkCommandBuffer cb, VkBuffer src, VkBuffer dst, uint32_t count,
                                         const VkBufferCopy* regions) {
  PFN_vkCmdCopyBuffer next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(cb));
    uint64_t bytes = 0;
    for (uint32_t i = 0; i < count; ++i) bytes += regions[i].size;
    Copies& c = d.recorded[cb];
    if (mapped_now(d, dst)) {
      c.to_host += 1;
      c.to_host_bytes += bytes;
    } else if (mapped_now(d, src)) {
      c.from_host += 1;
      c.from_host_bytes += bytes;
    }
    next = d.CmdCopyBuffer;
  }
  next(cb, src, dst, count, regions);
}

uint64_t texels_of(uint32_t count, const VkBufferImageCopy* regions) {
  uint64_t texels = 0;
  for (uint32_t i = 0; i < count; ++i)
    texels += uint64_t{regions[i].imageExtent.width} * regions[i].imageExtent.height * regions[i].imageExtent.depth *
              regions[i].imageSubresource.layerCount;
  return texels;
}

VKAPI_ATTR void VKAPI_CALL CmdCopyImageToBuffer(VkCommandBuffer cb, VkImage src, VkImageLayout layout, VkBuffer dst,
                                                uint32_t count, const VkBufferImageCopy* regions) {
  PFN_vkCmdCopyImageToBuffer next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(cb));
    if (mapped_now(d, dst)) {
      Copies& c = d.recorded[cb];
      c.to_host += 1;
      c.to_host_texels += texels_of(count, regions);
    }
    next = d.CmdCopyImageToBuffer;
  }
  next(cb, src, layout, dst, count, regions);
}

VKAPI_ATTR void VKAPI_CALL CmdCopyBufferToImage(VkCommandBuffer cb, VkBuffer src, VkImage dst, VkImageLayout layout,
                                                uint32_t count, const VkBufferImageCopy* regions) {
  PFN_vkCmdCopyBufferToImage next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(cb));
    if (mapped_now(d, src)) {
      Copies& c = d.recorded[cb];
      c.from_host += 1;
      c.from_host_texels += texels_of(count, regions);
    }
    next = d.CmdCopyBufferToImage;
  }
  next(cb, src, dst, layout, count, regions);
}

// Counts one command of `cb` in `field`; the next link's function.
template <class Fn>
Fn count_command(VkCommandBuffer cb, uint64_t Commands::*field, Fn DeviceData::*next) {
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  DeviceData& d = l.devices.at(key_of(cb));
  ++(d.commands[cb].*field);
  return d.*next;
}

VKAPI_ATTR void VKAPI_CALL CmdDispatch(VkCommandBuffer cb, uint32_t x, uint32_t y, uint32_t z) {
  count_command(cb, &Commands::dispatches, &DeviceData::CmdDispatch)(cb, x, y, z);
}

VKAPI_ATTR void VKAPI_CALL CmdDispatchIndirect(VkCommandBuffer cb, VkBuffer buffer, VkDeviceSize offset) {
  count_command(cb, &Commands::dispatches_indirect, &DeviceData::CmdDispatchIndirect)(cb, buffer, offset);
}

VKAPI_ATTR void VKAPI_CALL CmdPipelineBarrier(VkCommandBuffer cb, VkPipelineStageFlags src, VkPipelineStageFlags dst,
                                              VkDependencyFlags flags, uint32_t memory_count,
                                              const VkMemoryBarrier* memory, uint32_t buffer_count,
                                              const VkBufferMemoryBarrier* buffers, uint32_t image_count,
                                              const VkImageMemoryBarrier* images) {
  count_command(cb, &Commands::barriers, &DeviceData::CmdPipelineBarrier)(
      cb, src, dst, flags, memory_count, memory, buffer_count, buffers, image_count, images);
}

VKAPI_ATTR void VKAPI_CALL CmdPipelineBarrier2(VkCommandBuffer cb, const VkDependencyInfo* info) {
  count_command(cb, &Commands::barriers, &DeviceData::CmdPipelineBarrier2)(cb, info);
}

VKAPI_ATTR void VKAPI_CALL CmdPipelineBarrier2KHR(VkCommandBuffer cb, const VkDependencyInfo* info) {
  count_command(cb, &Commands::barriers, &DeviceData::CmdPipelineBarrier2KHR)(cb, info);
}

VKAPI_ATTR void VKAPI_CALL CmdTraceRaysKHR(VkCommandBuffer cb, const VkStridedDeviceAddressRegionKHR* raygen,
                                           const VkStridedDeviceAddressRegionKHR* miss,
                                           const VkStridedDeviceAddressRegionKHR* hit,
                                           const VkStridedDeviceAddressRegionKHR* callable, uint32_t width,
                                           uint32_t height, uint32_t depth) {
  count_command(cb, &Commands::trace_rays, &DeviceData::CmdTraceRaysKHR)(cb, raygen, miss, hit, callable, width,
                                                                         height, depth);
}

VKAPI_ATTR void VKAPI_CALL CmdTraceRaysIndirectKHR(VkCommandBuffer cb, const VkStridedDeviceAddressRegionKHR* raygen,
                                                   const VkStridedDeviceAddressRegionKHR* miss,
                                                   const VkStridedDeviceAddressRegionKHR* hit,
                                                   const VkStridedDeviceAddressRegionKHR* callable,
                                                   VkDeviceAddress address) {
  count_command(cb, &Commands::trace_rays, &DeviceData::CmdTraceRaysIndirectKHR)(cb, raygen, miss, hit, callable,
                                                                                 address);
}

// vkFlushMappedMemoryRanges and vkInvalidateMappedMemoryRanges: one event, their bytes.
template <PFN_vkFlushMappedMemoryRanges DeviceData::*Next>
VkResult ranges_call(const char* call, VkDevice device, uint32_t count, const VkMappedMemoryRange* ranges) {
  auto chain = caller_chain();
  PFN_vkFlushMappedMemoryRanges next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    DeviceData& d = l.devices.at(key_of(device));
    record(d, call, "", count, ranges_bytes(d, count, ranges), std::move(chain));
    next = d.*Next;
  }
  return next(device, count, ranges);
}

VKAPI_ATTR VkResult VKAPI_CALL FlushMappedMemoryRanges(VkDevice device, uint32_t count,
                                                       const VkMappedMemoryRange* ranges) {
  return ranges_call<&DeviceData::FlushMappedMemoryRanges>("vkFlushMappedMemoryRanges", device, count, ranges);
}

VKAPI_ATTR VkResult VKAPI_CALL InvalidateMappedMemoryRanges(VkDevice device, uint32_t count,
                                                            const VkMappedMemoryRange* ranges) {
  return ranges_call<&DeviceData::InvalidateMappedMemoryRanges>("vkInvalidateMappedMemoryRanges", device, count,
                                                                 ranges);
}

VKAPI_ATTR void VKAPI_CALL DestroyDevice(VkDevice device, const VkAllocationCallbacks* allocator) {
  const Key key = key_of(device);  // read before the driver frees the handle
  PFN_vkDestroyDevice next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    next = l.devices.at(key).DestroyDevice;
  }
  next(device, allocator);
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  auto it = l.devices.find(key);
  if (it == l.devices.end()) return;
  write_out(it->second);
  l.devices.erase(it);
}

// The device functions this layer intercepts, by name.
PFN_vkVoidFunction device_intercept(const char* name) {
  static const std::map<std::string, PFN_vkVoidFunction> table = {
      {"vkDestroyDevice", reinterpret_cast<PFN_vkVoidFunction>(&DestroyDevice)},
      {"vkQueueSubmit", reinterpret_cast<PFN_vkVoidFunction>(&QueueSubmit)},
      {"vkQueueSubmit2", reinterpret_cast<PFN_vkVoidFunction>(&QueueSubmit2)},
      {"vkQueueSubmit2KHR", reinterpret_cast<PFN_vkVoidFunction>(&QueueSubmit2KHR)},
      {"vkWaitForFences", reinterpret_cast<PFN_vkVoidFunction>(&WaitForFences)},
      {"vkResetFences", reinterpret_cast<PFN_vkVoidFunction>(&ResetFences)},
      {"vkDestroyFence", reinterpret_cast<PFN_vkVoidFunction>(&DestroyFence)},
      {"vkGetFenceStatus", reinterpret_cast<PFN_vkVoidFunction>(&GetFenceStatus)},
      {"vkQueueWaitIdle", reinterpret_cast<PFN_vkVoidFunction>(&QueueWaitIdle)},
      {"vkDeviceWaitIdle", reinterpret_cast<PFN_vkVoidFunction>(&DeviceWaitIdle)},
      {"vkWaitSemaphores", reinterpret_cast<PFN_vkVoidFunction>(&WaitSemaphores)},
      {"vkWaitSemaphoresKHR", reinterpret_cast<PFN_vkVoidFunction>(&WaitSemaphoresKHR)},
      {"vkGetQueryPoolResults", reinterpret_cast<PFN_vkVoidFunction>(&GetQueryPoolResults)},
      {"vkAllocateMemory", reinterpret_cast<PFN_vkVoidFunction>(&AllocateMemory)},
      {"vkFreeMemory", reinterpret_cast<PFN_vkVoidFunction>(&FreeMemory)},
      {"vkMapMemory", reinterpret_cast<PFN_vkVoidFunction>(&MapMemory)},
      {"vkUnmapMemory", reinterpret_cast<PFN_vkVoidFunction>(&UnmapMemory)},
      {"vkFlushMappedMemoryRanges", reinterpret_cast<PFN_vkVoidFunction>(&FlushMappedMemoryRanges)},
      {"vkInvalidateMappedMemoryRanges", reinterpret_cast<PFN_vkVoidFunction>(&InvalidateMappedMemoryRanges)},
      {"vkBindBufferMemory", reinterpret_cast<PFN_vkVoidFunction>(&BindBufferMemory)},
      {"vkBindBufferMemory2", reinterpret_cast<PFN_vkVoidFunction>(&BindBufferMemory2)},
      {"vkBindBufferMemory2KHR", reinterpret_cast<PFN_vkVoidFunction>(&BindBufferMemory2KHR)},
      {"vkBeginCommandBuffer", reinterpret_cast<PFN_vkVoidFunction>(&BeginCommandBuffer)},
      {"vkCmdCopyBuffer", reinterpret_cast<PFN_vkVoidFunction>(&CmdCopyBuffer)},
      {"vkCmdCopyImageToBuffer", reinterpret_cast<PFN_vkVoidFunction>(&CmdCopyImageToBuffer)},
      {"vkCmdCopyBufferToImage", reinterpret_cast<PFN_vkVoidFunction>(&CmdCopyBufferToImage)},
      {"vkCmdDispatch", reinterpret_cast<PFN_vkVoidFunction>(&CmdDispatch)},
      {"vkCmdDispatchIndirect", reinterpret_cast<PFN_vkVoidFunction>(&CmdDispatchIndirect)},
      {"vkCmdPipelineBarrier", reinterpret_cast<PFN_vkVoidFunction>(&CmdPipelineBarrier)},
      {"vkCmdPipelineBarrier2", reinterpret_cast<PFN_vkVoidFunction>(&CmdPipelineBarrier2)},
      {"vkCmdPipelineBarrier2KHR", reinterpret_cast<PFN_vkVoidFunction>(&CmdPipelineBarrier2KHR)},
      {"vkCmdTraceRaysKHR", reinterpret_cast<PFN_vkVoidFunction>(&CmdTraceRaysKHR)},
      {"vkCmdTraceRaysIndirectKHR", reinterpret_cast<PFN_vkVoidFunction>(&CmdTraceRaysIndirectKHR)},
  };
  auto it = table.find(name);
  return it != table.end() ? it->second : nullptr;
}

template <class Fn>
void load(DeviceData& d, const char* name, Fn& fn) {
  fn = reinterpret_cast<Fn>(d.gdpa(d.device, name));
}

// The next link's device functions; false when a core one is missing.
bool load_device(DeviceData& d) {
  load(d, "vkDestroyDevice", d.DestroyDevice);
  load(d, "vkQueueSubmit", d.QueueSubmit);
  load(d, "vkQueueSubmit2", d.QueueSubmit2);
  load(d, "vkQueueSubmit2KHR", d.QueueSubmit2KHR);
  load(d, "vkWaitForFences", d.WaitForFences);
  load(d, "vkResetFences", d.ResetFences);
  load(d, "vkDestroyFence", d.DestroyFence);
  load(d, "vkGetFenceStatus", d.GetFenceStatus);
  load(d, "vkQueueWaitIdle", d.QueueWaitIdle);
  load(d, "vkDeviceWaitIdle", d.DeviceWaitIdle);
  load(d, "vkWaitSemaphores", d.WaitSemaphores);
  load(d, "vkWaitSemaphoresKHR", d.WaitSemaphoresKHR);
  load(d, "vkGetQueryPoolResults", d.GetQueryPoolResults);
  load(d, "vkAllocateMemory", d.AllocateMemory);
  load(d, "vkFreeMemory", d.FreeMemory);
  load(d, "vkMapMemory", d.MapMemory);
  load(d, "vkUnmapMemory", d.UnmapMemory);
  load(d, "vkFlushMappedMemoryRanges", d.FlushMappedMemoryRanges);
  load(d, "vkInvalidateMappedMemoryRanges", d.InvalidateMappedMemoryRanges);
  load(d, "vkBindBufferMemory", d.BindBufferMemory);
  load(d, "vkBindBufferMemory2", d.BindBufferMemory2);
  load(d, "vkBindBufferMemory2KHR", d.BindBufferMemory2KHR);
  load(d, "vkBeginCommandBuffer", d.BeginCommandBuffer);
  load(d, "vkCmdCopyBuffer", d.CmdCopyBuffer);
  load(d, "vkCmdCopyImageToBuffer", d.CmdCopyImageToBuffer);
  load(d, "vkCmdCopyBufferToImage", d.CmdCopyBufferToImage);
  load(d, "vkCmdDispatch", d.CmdDispatch);
  load(d, "vkCmdDispatchIndirect", d.CmdDispatchIndirect);
  load(d, "vkCmdPipelineBarrier", d.CmdPipelineBarrier);
  load(d, "vkCmdPipelineBarrier2", d.CmdPipelineBarrier2);  // these four: where the device offers them
  load(d, "vkCmdPipelineBarrier2KHR", d.CmdPipelineBarrier2KHR);
  load(d, "vkCmdTraceRaysKHR", d.CmdTraceRaysKHR);
  load(d, "vkCmdTraceRaysIndirectKHR", d.CmdTraceRaysIndirectKHR);
  return d.CmdDispatch && d.CmdDispatchIndirect && d.CmdPipelineBarrier && d.BindBufferMemory && d.BeginCommandBuffer && d.CmdCopyBuffer && d.CmdCopyImageToBuffer &&
         d.CmdCopyBufferToImage && d.DestroyDevice && d.QueueSubmit && d.WaitForFences && d.ResetFences &&
         d.DestroyFence && d.GetFenceStatus && d.QueueWaitIdle && d.DeviceWaitIdle && d.GetQueryPoolResults &&
         d.AllocateMemory && d.FreeMemory && d.MapMemory && d.UnmapMemory && d.FlushMappedMemoryRanges &&
         d.InvalidateMappedMemoryRanges;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL GetDeviceProcAddr(VkDevice device, const char* name);

// ---- instance functions --------------------------------------------------------

template <class Info>
Info* link_info(const void* next, VkStructureType type) {
  for (auto* s = static_cast<const VkBaseInStructure*>(next); s != nullptr; s = s->pNext) {
    auto* info = reinterpret_cast<Info*>(const_cast<VkBaseInStructure*>(s));
    if (s->sType == type && info->function == VK_LAYER_LINK_INFO) return info;
  }
  return nullptr;
}

VKAPI_ATTR VkResult VKAPI_CALL CreateInstance(const VkInstanceCreateInfo* info, const VkAllocationCallbacks* allocator,
                                              VkInstance* instance) {
  auto* link = link_info<VkLayerInstanceCreateInfo>(info->pNext, VK_STRUCTURE_TYPE_LOADER_INSTANCE_CREATE_INFO);
  if (link == nullptr) return VK_ERROR_INITIALIZATION_FAILED;
  const PFN_vkGetInstanceProcAddr gipa = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  auto create = reinterpret_cast<PFN_vkCreateInstance>(gipa(VK_NULL_HANDLE, "vkCreateInstance"));
  const VkResult r = create(info, allocator, instance);
  if (r != VK_SUCCESS) return r;
  InstanceData data;
  data.instance = *instance;
  data.gipa = gipa;
  data.destroy = reinterpret_cast<PFN_vkDestroyInstance>(gipa(*instance, "vkDestroyInstance"));
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  l.instances[key_of(*instance)] = data;
  return VK_SUCCESS;
}

VKAPI_ATTR void VKAPI_CALL DestroyInstance(VkInstance instance, const VkAllocationCallbacks* allocator) {
  InstanceData data;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    auto it = l.instances.find(key_of(instance));
    if (it == l.instances.end()) return;
    data = it->second;
    l.instances.erase(it);
  }
  data.destroy(instance, allocator);
}

VKAPI_ATTR VkResult VKAPI_CALL CreateDevice(VkPhysicalDevice physical, const VkDeviceCreateInfo* info,
                                            const VkAllocationCallbacks* allocator, VkDevice* device) {
  auto* link = link_info<VkLayerDeviceCreateInfo>(info->pNext, VK_STRUCTURE_TYPE_LOADER_DEVICE_CREATE_INFO);
  if (link == nullptr) return VK_ERROR_INITIALIZATION_FAILED;
  const PFN_vkGetInstanceProcAddr gipa = link->u.pLayerInfo->pfnNextGetInstanceProcAddr;
  const PFN_vkGetDeviceProcAddr gdpa = link->u.pLayerInfo->pfnNextGetDeviceProcAddr;
  link->u.pLayerInfo = link->u.pLayerInfo->pNext;
  VkInstance instance = VK_NULL_HANDLE;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    auto it = l.instances.find(key_of(physical));  // a physical device shares its instance's key
    if (it != l.instances.end()) instance = it->second.instance;
  }
  auto create = reinterpret_cast<PFN_vkCreateDevice>(gipa(instance, "vkCreateDevice"));
  const VkResult r = create(physical, info, allocator, device);
  if (r != VK_SUCCESS) return r;
  DeviceData d;
  d.device = *device;
  d.gdpa = gdpa;
  auto properties =
      reinterpret_cast<PFN_vkGetPhysicalDeviceProperties>(gipa(instance, "vkGetPhysicalDeviceProperties"));
  VkPhysicalDeviceProperties p{};
  if (properties != nullptr) properties(physical, &p);
  d.name = p.deviceName;
  if (!load_device(d)) {
    if (d.DestroyDevice != nullptr) d.DestroyDevice(*device, allocator);
    *device = VK_NULL_HANDLE;
    return VK_ERROR_INITIALIZATION_FAILED;
  }
  Layer& l = layer();
  std::lock_guard lock(l.mutex);
  l.devices[key_of(*device)] = std::move(d);
  return VK_SUCCESS;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL GetInstanceProcAddr(VkInstance instance, const char* name);

PFN_vkVoidFunction instance_intercept(const char* name) {
  if (std::strcmp(name, "vkGetInstanceProcAddr") == 0)
    return reinterpret_cast<PFN_vkVoidFunction>(&GetInstanceProcAddr);
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&GetDeviceProcAddr);
  if (std::strcmp(name, "vkCreateInstance") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&CreateInstance);
  if (std::strcmp(name, "vkDestroyInstance") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&DestroyInstance);
  if (std::strcmp(name, "vkCreateDevice") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&CreateDevice);
  return nullptr;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL GetInstanceProcAddr(VkInstance instance, const char* name) {
  if (PFN_vkVoidFunction f = instance_intercept(name)) return f;
  if (instance == VK_NULL_HANDLE) return nullptr;
  PFN_vkGetInstanceProcAddr next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    auto it = l.instances.find(key_of(instance));
    if (it == l.instances.end()) return nullptr;
    next = it->second.gipa;
  }
  PFN_vkVoidFunction f = next(instance, name);
  // A device function asked of the instance: ours where the next link has one.
  if (f != nullptr) {
    if (PFN_vkVoidFunction mine = device_intercept(name)) return mine;
  }
  return f;
}

VKAPI_ATTR PFN_vkVoidFunction VKAPI_CALL GetDeviceProcAddr(VkDevice device, const char* name) {
  PFN_vkGetDeviceProcAddr next = nullptr;
  {
    Layer& l = layer();
    std::lock_guard lock(l.mutex);
    auto it = l.devices.find(key_of(device));
    if (it == l.devices.end()) return nullptr;
    next = it->second.gdpa;
  }
  PFN_vkVoidFunction f = next(device, name);
  if (std::strcmp(name, "vkGetDeviceProcAddr") == 0) return reinterpret_cast<PFN_vkVoidFunction>(&GetDeviceProcAddr);
  if (f == nullptr) return nullptr;  // not offered below (an extension not enabled, a newer core version)
  if (PFN_vkVoidFunction mine = device_intercept(name)) return mine;
  return f;
}

}  // namespace

extern "C" VK_LAYER_EXPORT VKAPI_ATTR VkResult VKAPI_CALL
vkNegotiateLoaderLayerInterfaceVersion(VkNegotiateLayerInterface* interface) {
  // Version 2: the loader takes our proc-addr functions from here, not from exported symbols.
  if (interface == nullptr || interface->sType != LAYER_NEGOTIATE_INTERFACE_STRUCT ||
      interface->loaderLayerInterfaceVersion < 2)
    return VK_ERROR_INITIALIZATION_FAILED;
  interface->loaderLayerInterfaceVersion = 2;
  interface->pfnGetInstanceProcAddr = &GetInstanceProcAddr;
  interface->pfnGetDeviceProcAddr = &GetDeviceProcAddr;
  interface->pfnGetPhysicalDeviceProcAddr = nullptr;
  return VK_SUCCESS;
}
