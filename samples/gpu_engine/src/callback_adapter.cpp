// CallbackAdapter: a headless Vulkan device of its own, a GpuTracer on it, and
// per batch: pack rays -> submit record_trace -> wait -> copy colours out.
#include <gpu_engine/callback_adapter.hpp>
#include <gpu_engine/rt_device.hpp>
#include <gpu_engine/validation_messenger.hpp>

#include <foveation/ray_batch_reader.hpp>

#include "command_slot.hpp"
#include "icd_pin.h"
#include "vk_buffer.hpp"
#include "vk_helpers.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <utility>

namespace foveart::gpu_engine {
namespace {

constexpr uint32_t kGroupSize = 64;              // the trace shader's local_size_x
constexpr uint32_t kMaxRaysPerSubmit = 1u << 18;  // larger batches go in several submissions
constexpr uint64_t kFenceTimeoutNs = 120ull * 1000 * 1000 * 1000;

// Lower is preferred.
int device_rank(VkPhysicalDeviceType type, bool prefer_cpu) {
  if (prefer_cpu) return type == VK_PHYSICAL_DEVICE_TYPE_CPU ? 0 : 1;
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

uint32_t compute_family(VkPhysicalDevice d) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(d, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(d, &count, families.data());
  for (uint32_t i = 0; i < count; ++i)
    if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) != 0 && families[i].queueCount > 0) return i;
  return UINT32_MAX;
}

struct PackedRay {
  float origin_sample_x[4];
  float direction_sample_y[4];
};
static_assert(sizeof(PackedRay) == 32, "the trace shader's DeviceRay is 32 bytes");

}  // namespace

struct CallbackAdapter::Impl {
  // Vulkan objects, destroyed in reverse order by the destructor.
  ValidationMessenger validation;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t family = UINT32_MAX;
  VkQueue queue = VK_NULL_HANDLE;
  std::string name;
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  bool ray_tracing = false;  // the device was created with the ray-tracing extensions
  CommandSlot commands;
  std::unique_ptr<GpuTracer> tracer;

  // Guarded by `mutex`: the staging buffers and the one submission in flight.
  mutable std::mutex mutex;
  // Host-visible on purpose: the host writes every call's rays and reads its colours back,
  // each byte once per call, so a device-local copy would only add a staging copy each way;
  // the scene they are traced against is the tracer's, in device-local memory.
  MappedBuffer count_buffer;  // XrFoveatedDeviceRayCountFOVEART
  MappedBuffer rays;          // capacity x 32 bytes
  MappedBuffer colors;        // capacity x vec4
  uint32_t capacity = 0;
  std::vector<uint32_t> slot;  // per ray of the current chunk: its packed index, or UINT32_MAX (black)
  uint64_t skipped_primary = 0;  // rays given black on the host: primary rays as engine::Tracer counts them
  std::string last_error;        // why the last failed batch failed

  ~Impl() {
    if (device != VK_NULL_HANDLE) vkDeviceWaitIdle(device);
    tracer.reset();
    count_buffer.destroy();
    rays.destroy();
    colors.destroy();
    commands.destroy();
    if (device != VK_NULL_HANDLE) vkDestroyDevice(device, nullptr);
    validation.destroy(instance);
    if (instance != VK_NULL_HANDLE) vkDestroyInstance(instance, nullptr);
  }

  bool create_device(const CallbackAdapterOptions& options, std::string* error);
  bool create_instance(const CallbackAdapterOptions& options, std::string* error);
  bool pick_physical_device(const CallbackAdapterOptions& options, std::string* error);
  bool create_logical_device(const CallbackAdapterOptions& options, std::string* error);
  bool create_submission(std::string* error);
  bool ensure_capacity(uint32_t rays_needed, std::string* error);
  int32_t trace_chunk(const foveation::RayBatchReader& batch_rays, uint32_t first, uint32_t n);
  uint32_t pack_rays(const foveation::RayBatchReader& batch_rays, uint32_t first, uint32_t n);
  int32_t record_trace(const FoveartRayBatch& batch, uint32_t valid);
  void unpack_colors(const FoveartRayBatch& batch, uint32_t first, uint32_t n, float* out_depth) const;
};

bool CallbackAdapter::Impl::create_device(const CallbackAdapterOptions& options, std::string* error) {
  return create_instance(options, error) && pick_physical_device(options, error) &&
         create_logical_device(options, error) && create_submission(error);
}

// The instance, with the validation layer (errors collected) when asked for and installed.
bool CallbackAdapter::Impl::create_instance(const CallbackAdapterOptions& options, std::string* error) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "foveart_gpu_engine_callback_adapter";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
  validation.chain(options.validate, &info);
  const VkResult r = vkCreateInstance(&info, nullptr, &instance);
  if (r != VK_SUCCESS) {
    instance = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateInstance (is a Vulkan driver installed?)", r));
  }
  validation.register_for(instance);
  return true;
}

// The preferred Vulkan 1.1 device with a compute queue (device_rank).
bool CallbackAdapter::Impl::pick_physical_device(const CallbackAdapterOptions& options, std::string* error) {
  uint32_t count = 0;
  VkResult r = vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  if (r == VK_SUCCESS && count > 0) r = vkEnumeratePhysicalDevices(instance, &count, devices.data());
  if (r != VK_SUCCESS && r != VK_INCOMPLETE) return fail(error, vk_error("vkEnumeratePhysicalDevices", r));
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(d, &p);
    if (p.apiVersion < VK_API_VERSION_1_1 || compute_family(d) == UINT32_MAX) continue;
    if (physical == VK_NULL_HANDLE ||
        device_rank(p.deviceType, options.prefer_cpu) < device_rank(type, options.prefer_cpu)) {
      physical = d;
      name = p.deviceName;
      type = p.deviceType;
    }
  }
  if (physical == VK_NULL_HANDLE)
    return fail(error, "gpu_engine: no Vulkan 1.1 device with a compute queue (" + std::to_string(count) +
                                " device(s) found)");
  family = compute_family(physical);
  // The driver made its process-lifetime allocations while enumerating: keep it mapped so
  // that LeakSanitizer names them at exit, as the simulated runtime does (icd_pin.h).
  foveart::sim::pin_loaded_vulkan_icds_and_layers();
  return true;
}

// The device and its compute queue, with the ray-tracing extensions where offered and allowed.
bool CallbackAdapter::Impl::create_logical_device(const CallbackAdapterOptions& options, std::string* error) {
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{};
  queue_info.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  queue_info.queueFamilyIndex = family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkPhysicalDeviceFeatures supported{};
  vkGetPhysicalDeviceFeatures(physical, &supported);
  VkPhysicalDeviceFeatures enabled{};
  enabled.shaderStorageBufferArrayDynamicIndexing = supported.shaderStorageBufferArrayDynamicIndexing;
  VkDeviceCreateInfo device_info{};
  device_info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.pEnabledFeatures = &enabled;
  // The ray-tracing pipeline backend's extensions where the device offers them
  // and the tracer may use them.
  RayTracingDeviceSupport rt_support(physical);
  std::vector<const char*> device_extensions;
  ray_tracing =
      options.tracer.backend != GpuBackend::compute && rt_support.enable(&device_info, &device_extensions);
  const VkResult r = vkCreateDevice(physical, &device_info, nullptr, &device);
  if (r != VK_SUCCESS) {
    device = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateDevice", r) + " on " + name);
  }
  vkGetDeviceQueue(device, family, 0, &queue);
  return true;
}

// The one command buffer, its fence and the ray count buffer every submission uses.
bool CallbackAdapter::Impl::create_submission(std::string* error) {
  if (!commands.create(device, family, error)) return false;
  return count_buffer.create(physical, device, sizeof(XrFoveatedDeviceRayCountFOVEART), nullptr, error,
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT);
}

// Rays and colours for at least `rays_needed` rays, grown by doubling.
bool CallbackAdapter::Impl::ensure_capacity(uint32_t rays_needed, std::string* error) {
  if (rays_needed <= capacity) return true;
  uint32_t grown = std::max<uint32_t>(capacity, 4096);
  while (grown < rays_needed) grown *= 2;
  capacity = 0;
  if (!rays.create(physical, device, VkDeviceSize{grown} * sizeof(PackedRay), nullptr, error) ||
      !colors.create(physical, device, VkDeviceSize{grown} * 16, nullptr, error))
    return false;
  capacity = grown;
  return true;
}

int32_t CallbackAdapter::Impl::trace_chunk(const foveation::RayBatchReader& batch_rays, uint32_t first, uint32_t n) {
  std::string error;
  if (!ensure_capacity(n, &error)) {
    last_error = error;
    return FOVEART_RESULT_ERROR_OUT_OF_MEMORY;
  }
  const FoveartRayBatch& batch = batch_rays.batch();
  const uint32_t valid = pack_rays(batch_rays, first, n);
  skipped_primary += n - valid;
  if (valid > 0) {
    if (const int32_t r = record_trace(batch, valid); r != FOVEART_RESULT_SUCCESS) return r;
    if (!commands.submit_and_wait(queue, kFenceTimeoutNs, "ray batch", &last_error))
      return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  }
  unpack_colors(batch, first, n, batch_rays.out_depth_m());
  return FOVEART_RESULT_SUCCESS;
}

// Packs rays [first, first + n) of the batch, the valid ones only; `slot` says
// where each went (UINT32_MAX: black with no depth, as engine::Tracer leaves it). Returns how many.
uint32_t CallbackAdapter::Impl::pack_rays(const foveation::RayBatchReader& batch_rays, uint32_t first, uint32_t n) {
  const FoveartRayBatch& batch = batch_rays.batch();
  auto* packed = static_cast<PackedRay*>(rays.mapped());
  slot.assign(n, UINT32_MAX);
  uint32_t valid = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t r = first + i;
    glm::vec3 o, d;
    if (!batch_rays.ray(r, &o, &d)) continue;
    const float sx = batch.sample_px != nullptr ? batch.sample_px[2 * r] : 0.0f;
    const float sy = batch.sample_px != nullptr ? batch.sample_px[2 * r + 1] : 0.0f;
    packed[valid] = PackedRay{{o.x, o.y, o.z, sx}, {d.x, d.y, d.z, sy}};
    slot[i] = valid++;
  }
  return valid;
}

// The count header for `valid` packed rays, and the command buffer: barriers around the tracer's trace.
int32_t CallbackAdapter::Impl::record_trace(const FoveartRayBatch& batch, uint32_t valid) {
  XrFoveatedDeviceRayCountFOVEART header{};
  header.count = valid;
  header.dispatch64[0] = (valid + kGroupSize - 1) / kGroupSize;
  header.dispatch64[1] = 1;
  header.dispatch64[2] = 1;
  header.traceRays[0] = valid;
  header.traceRays[1] = 1;
  header.traceRays[2] = 1;
  std::memcpy(count_buffer.mapped(), &header, sizeof(header));

  if (!commands.begin(&last_error)) return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  const VkCommandBuffer cb = commands.cb();
  // Host writes of rays and count -> the shader's reads and the indirect dispatch's.
  VkMemoryBarrier before{};
  before.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  before.srcAccessMask = VK_ACCESS_HOST_WRITE_BIT;
  before.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
  const VkPipelineStageFlags trace_stage = tracer->backend() == GpuBackend::ray_tracing_pipeline
                                               ? VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR
                                               : VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_HOST_BIT, trace_stage | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &before,
                       0, nullptr, 0, nullptr);
  XrFoveatedDeviceRayBatchFOVEART device_batch{};
  device_batch.type = XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART;
  device_batch.frameIndex = batch.frame_index;
  device_batch.view = batch.view;
  device_batch.rayCapacity = capacity;
  device_batch.raysPerPoint = 1;
  device_batch.rayCount = {count_buffer.buffer(), 0, count_buffer.size()};
  device_batch.rays = {rays.buffer(), 0, rays.size()};
  device_batch.pointIndex = {VK_NULL_HANDLE, 0, 0};  // the trace does not read it
  device_batch.colors = {colors.buffer(), 0, colors.size()};
  device_batch.commandBuffer = cb;
  if (!tracer->record_trace(device_batch, &last_error)) {
    commands.abandon();
    return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  }
  // The shader's writes (colours, the tracer's counters) -> host reads.
  VkMemoryBarrier after{};
  after.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  after.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  after.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cb, trace_stage, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &after, 0, nullptr, 0, nullptr);
  return FOVEART_RESULT_SUCCESS;
}

// The colours (clamped to >= 0, black if not finite) and depths of rays [first, first + n) into the batch.
void CallbackAdapter::Impl::unpack_colors(const FoveartRayBatch& batch, uint32_t first, uint32_t n,
                                          float* out_depth) const {
  const auto* rgbd = static_cast<const float*>(colors.mapped());
  for (uint32_t i = 0; i < n; ++i) {
    float* out = batch.out_rgb + 3 * static_cast<size_t>(first + i);
    if (slot[i] == UINT32_MAX) {
      out[0] = out[1] = out[2] = 0.0f;
      if (out_depth != nullptr) out_depth[first + i] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
    const float* c = rgbd + 4 * static_cast<size_t>(slot[i]);
    const bool finite = std::isfinite(c[0] + c[1] + c[2]);
    for (int k = 0; k < 3; ++k) out[k] = finite ? std::max(c[k], 0.0f) : 0.0f;
    if (out_depth != nullptr) {
      const float depth = c[3];
      // +inf (a miss) stays +INFINITY whatever the device made of it; NaN: none given.
      out_depth[first + i] = std::isnan(depth)                                ? depth
                             : (std::isinf(depth) || depth >= 1e30f) ? std::numeric_limits<float>::infinity()
                                                                             : depth;
    }
  }
}

CallbackAdapter::CallbackAdapter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CallbackAdapter::~CallbackAdapter() = default;

std::unique_ptr<CallbackAdapter> CallbackAdapter::create(engine::Scene scene, std::string* error) {
  return create(std::move(scene), CallbackAdapterOptions{}, error);
}

std::unique_ptr<CallbackAdapter> CallbackAdapter::create(engine::Scene scene, const CallbackAdapterOptions& options,
                                                         std::string* error) {
  try {
    auto impl = std::make_unique<Impl>();
    if (!impl->create_device(options, error)) return nullptr;
    GpuContext context{impl->physical, impl->device, impl->family, impl->queue};
    context.ray_tracing_enabled = impl->ray_tracing;
    std::string tracer_error;
    impl->tracer = GpuTracer::create(context, std::move(scene), options.tracer, &tracer_error);
    if (!impl->tracer) {
      fail(error, tracer_error + " (device " + impl->name + ")");
      return nullptr;
    }
    return std::unique_ptr<CallbackAdapter>(new CallbackAdapter(std::move(impl)));
  } catch (const std::exception& e) {
    fail(error, std::string("gpu_engine: ") + e.what());
    return nullptr;
  }
}

int32_t CallbackAdapter::trace(const FoveartRayBatch* batch) noexcept {
  foveation::RayBatchReader batch_rays;
  if (const int32_t r = foveation::RayBatchReader::read(batch, &batch_rays);
      r != FOVEART_RESULT_SUCCESS || batch_rays.size() == 0)
    return r;
  try {
    std::lock_guard lock(impl_->mutex);
    for (uint32_t first = 0; first < batch_rays.size(); first += kMaxRaysPerSubmit) {
      const uint32_t n = std::min(kMaxRaysPerSubmit, batch_rays.size() - first);
      const int32_t status = impl_->trace_chunk(batch_rays, first, n);
      if (status != FOVEART_RESULT_SUCCESS) return status;
    }
    return FOVEART_RESULT_SUCCESS;
  } catch (const std::bad_alloc&) {
    return FOVEART_RESULT_ERROR_OUT_OF_MEMORY;
  } catch (...) {
    return FOVEART_RESULT_ERROR_ENGINE_FAILURE;
  }
}

const std::string& CallbackAdapter::device_name() const { return impl_->name; }
std::string CallbackAdapter::last_error() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->last_error;
}
const char* CallbackAdapter::backend_name() const { return impl_->tracer->backend_name(); }
bool CallbackAdapter::device_is_cpu() const { return impl_->type == VK_PHYSICAL_DEVICE_TYPE_CPU; }
bool CallbackAdapter::validated() const { return impl_->validation.active(); }
std::vector<std::string> CallbackAdapter::validation_errors() const {
  return impl_->validation.errors();
}

const engine::Scene& CallbackAdapter::scene() const { return impl_->tracer->scene(); }
engine::Effects CallbackAdapter::scene_effects() const { return impl_->tracer->scene_effects(); }
engine::Effects CallbackAdapter::effects() const { return impl_->tracer->effects(); }

engine::RayCounts CallbackAdapter::counts() const {
  std::lock_guard lock(impl_->mutex);
  engine::RayCounts c = impl_->tracer->counts();
  c.primary += impl_->skipped_primary;
  return c;
}

void CallbackAdapter::reset_counts() {
  std::lock_guard lock(impl_->mutex);
  impl_->tracer->reset_counts();
  impl_->skipped_primary = 0;
}

}  // namespace foveart::gpu_engine

extern "C" int32_t foveart_gpu_engine_trace_rays(void* user_data, const FoveartRayBatch* batch) {
  if (!user_data) return FOVEART_RESULT_ERROR_INVALID_ARGUMENT;
  return static_cast<foveart::gpu_engine::CallbackAdapter*>(user_data)->trace(batch);
}
