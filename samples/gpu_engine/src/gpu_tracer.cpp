// GpuTracer: the backend chosen, the scene uploaded once, two pipelines (the
// layer's device rays, whole images): compute (trace.comp, full.comp) or
// ray tracing (RtPipelineTracer: trace.rgen, full.rgen), and their recording.
// Descriptor sets, the scene's storage buffers (device-local, filled through
// staging), its textures (SceneTextures, binding 6) and the ray counters
// (host-visible: the host reads and resets them) are the same for both
// backends; set 0, binding 0 is the BVH's nodes or the TLAS, binding 1 the
// BVH's leaf entries or RtScene::prims.
#include <gpu_engine/gpu_tracer.hpp>

#include "rt_pipeline_tracer.hpp"
#include "vk_helpers.hpp"
#include "scene_data.hpp"
#include "scene_textures.hpp"
#include "vk_buffer.hpp"

#include <gpu_engine/rt_device.hpp>

#include <foveation/eye_rays.hpp>

#include <gpu_engine_shaders/full.spv.h>
#include <gpu_engine_shaders/trace.spv.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <exception>
#include <map>
#include <type_traits>
#include <utility>

namespace foveart::gpu_engine {
namespace {

constexpr uint32_t kSceneBindings = 9;    // scene_data.glsl, set 0
constexpr uint32_t kTextureBinding = 6;   // scene_textures[kTextureSlots]
constexpr uint32_t kCounterBinding = 8;   // the ray counters
constexpr uint32_t kTraceBindings = 4;    // trace.comp, set 1: rayCount, rays, colors, footprints
constexpr uint32_t kFullBindings = 1;     // full.comp, set 1: pixels
constexpr uint32_t kCachedSets = 32;      // per-call descriptor sets kept before the pool is reset
constexpr uint32_t kTraceGroup = 64;      // trace.comp local_size_x
constexpr uint32_t kFullGroup = 8;        // full.comp local_size_x and _y
constexpr uint32_t kCounterWords = 8;     // scene_data.glsl's counters[]: 4 ray kinds, 2 x (low, high) work

struct FullPush {  // full.comp's push constants
  float tans[4];
  float position[4];
  float orientation[4];
  uint32_t size_spp_seed[4];
  uint32_t seed_hi[4];
};
static_assert(sizeof(FullPush) == 80);

// Inner nodes plus non-empty leaves: the most nodes one traversal visits.
uint64_t count_bvh_nodes(const BvhData& bvh) {
  uint64_t leaves = 0;
  for (const GpuNode& n : bvh.nodes)
    for (const uint32_t child : {n.left, n.right})
      if ((child & kLeafBit) != 0u && child != kEmptyChild) ++leaves;
  return bvh.nodes.size() + leaves;
}

// The struct of `type` in a batch's next chain, or null (OpenXR's rule: unknown types are skipped).
template <class T>
const T* find_chained(const void* next, XrStructureType type) {
  for (auto* s = static_cast<const XrBaseInStructure*>(next); s != nullptr; s = s->next)
    if (s->type == type) return reinterpret_cast<const T*>(s);
  return nullptr;
}

uint64_t handle_bits(VkBuffer b) {
  uint64_t v = 0;
  std::memcpy(&v, &b, sizeof(b));
  return v;
}

}  // namespace

struct GpuTracer::Impl {
  GpuContext ctx;
  GpuTracerOptions options;
  engine::Scene scene;
  engine::Effects scene_effects;
  engine::Effects effects;
  VkPhysicalDeviceLimits limits{};
  std::string device_name;
  GpuBackend backend = GpuBackend::compute;  // the one chosen
  std::string backend_fallback;                 // automatic fell back to compute: why
  uint64_t bvh_node_count = 0;                  // compute: inner nodes + non-empty leaves
  uint32_t bvh_stack_entries = 1;               // compute: the traversal stack's size (bvh_inner_levels)
  VkShaderStageFlags stages = VK_SHADER_STAGE_COMPUTE_BIT;
  VkShaderStageFlags push_stage = VK_SHADER_STAGE_COMPUTE_BIT;
  VkPipelineBindPoint bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  VkPipelineStageFlags pipeline_stage = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
  std::unique_ptr<RtPipelineTracer> rt;  // ray_tracing_pipeline only

  // The scene: device-local where the device allows (filled through staging at
  // create()); the ray counters host-visible, as the host reads and resets them
  // between submissions (counts(), reset_counts()).
  std::shared_ptr<MemoryLedger> ledger;
  std::array<DeviceBuffer, kCounterBinding> buffers;  // by binding; none at kTextureBinding
  SceneTextures textures;                             // kTextureBinding
  MappedBuffer counters;                              // kCounterBinding
  VkDescriptorSetLayout scene_layout = VK_NULL_HANDLE;
  VkDescriptorSetLayout trace_layout = VK_NULL_HANDLE;
  VkDescriptorSetLayout full_layout = VK_NULL_HANDLE;
  VkPipelineLayout trace_pipeline_layout = VK_NULL_HANDLE;
  VkPipelineLayout full_pipeline_layout = VK_NULL_HANDLE;
  VkPipeline trace_pipeline = VK_NULL_HANDLE;
  VkPipeline full_pipeline = VK_NULL_HANDLE;
  VkDescriptorPool scene_pool = VK_NULL_HANDLE;
  VkDescriptorPool call_pool = VK_NULL_HANDLE;
  VkDescriptorSet scene_set = VK_NULL_HANDLE;
  // (kind, buffer, offset, size per binding) -> set; see record_* for why reuse is safe.
  std::map<std::array<uint64_t, 1 + 3 * kTraceBindings>, VkDescriptorSet> call_sets;
  MappedBuffer no_footprints;  // zeros: the footprints of a batch that has none (texture level 0)
  // Full call pools replaced by new ones while a frame in flight may still use
  // their sets: destroyed once the trace's frame index is a frame slot round
  // past the last frame that could (the header's Lifetime clause).
  struct RetiredPool {
    VkDescriptorPool pool = VK_NULL_HANDLE;
    uint64_t frame_index = 0;
  };
  std::vector<RetiredPool> retired_pools;
  uint64_t trace_frame_index = 0;  // the newest trace call's
  BatchChain last_chain;           // the last trace call's batch

  ~Impl();
  bool choose_backend(std::string* error);
  bool create(std::string* error);
  bool check_device(std::string* error);
  bool upload_scene(const SceneData& data, std::string* error);
  bool write_scene_set(std::string* error);
  bool create_layouts(std::string* error);
  VkResult make_call_pool(VkDescriptorPool* out) const;
  bool renew_call_pool(std::string* error);
  bool create_pipeline(const uint32_t* code, size_t bytes, VkPipelineLayout layout, VkPipeline* out,
                       std::string* error);
  VkDescriptorSet call_set(uint64_t kind, VkDescriptorSetLayout layout, const VkDescriptorBufferInfo* infos,
                           uint32_t count, std::string* error);
  bool check_range(const char* what, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size, VkDeviceSize min_size,
                   std::string* error) const;
  void barrier_counters(VkCommandBuffer cb) const;
  bool record_trace(const XrFoveatedDeviceRayBatchFOVEART& batch, std::string* error);
  bool record_full(VkCommandBuffer cb, const FoveartEyeView& view, uint32_t spp, uint64_t seed, VkBuffer out,
                   VkDeviceSize offset, std::string* error);
};

GpuTracer::Impl::~Impl() {
  VkDevice d = ctx.device;
  if (d == VK_NULL_HANDLE) return;
  rt.reset();
  if (trace_pipeline) vkDestroyPipeline(d, trace_pipeline, nullptr);
  if (full_pipeline) vkDestroyPipeline(d, full_pipeline, nullptr);
  if (trace_pipeline_layout) vkDestroyPipelineLayout(d, trace_pipeline_layout, nullptr);
  if (full_pipeline_layout) vkDestroyPipelineLayout(d, full_pipeline_layout, nullptr);
  if (scene_pool) vkDestroyDescriptorPool(d, scene_pool, nullptr);  // frees its sets
  if (call_pool) vkDestroyDescriptorPool(d, call_pool, nullptr);
  for (const RetiredPool& p : retired_pools) vkDestroyDescriptorPool(d, p.pool, nullptr);
  if (scene_layout) vkDestroyDescriptorSetLayout(d, scene_layout, nullptr);
  if (trace_layout) vkDestroyDescriptorSetLayout(d, trace_layout, nullptr);
  if (full_layout) vkDestroyDescriptorSetLayout(d, full_layout, nullptr);
  for (DeviceBuffer& b : buffers) b.destroy();
  textures.destroy();
  counters.destroy();
  no_footprints.destroy();
}

// Descriptor set layouts, pipeline layouts and pools.
bool GpuTracer::Impl::create_layouts(std::string* error) {
  auto make_layout = [&](uint32_t n, VkDescriptorSetLayout* out) {
    std::array<VkDescriptorSetLayoutBinding, kSceneBindings> b{};
    for (uint32_t i = 0; i < n; ++i) {
      b[i].binding = i;
      b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      b[i].descriptorCount = 1;
      b[i].stageFlags = stages;
    }
    if (n == kSceneBindings && backend == GpuBackend::ray_tracing_pipeline)
      b[0].descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;  // the TLAS
    if (n == kSceneBindings) {
      b[kTextureBinding].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
      b[kTextureBinding].descriptorCount = kTextureSlots;
    }
    VkDescriptorSetLayoutCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    info.bindingCount = n;
    info.pBindings = b.data();
    return vkCreateDescriptorSetLayout(ctx.device, &info, nullptr, out);
  };
  VkResult r = make_layout(kSceneBindings, &scene_layout);
  if (r == VK_SUCCESS) r = make_layout(kTraceBindings, &trace_layout);
  if (r == VK_SUCCESS) r = make_layout(kFullBindings, &full_layout);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateDescriptorSetLayout", r));

  auto make_pipeline_layout = [&](VkDescriptorSetLayout call_layout, uint32_t push_bytes, VkPipelineLayout* out) {
    const VkDescriptorSetLayout sets[2] = {scene_layout, call_layout};
    VkPushConstantRange push{push_stage, 0, push_bytes};
    VkPipelineLayoutCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    info.setLayoutCount = 2;
    info.pSetLayouts = sets;
    info.pushConstantRangeCount = push_bytes > 0 ? 1 : 0;
    info.pPushConstantRanges = push_bytes > 0 ? &push : nullptr;
    return vkCreatePipelineLayout(ctx.device, &info, nullptr, out);
  };
  r = make_pipeline_layout(trace_layout, 0, &trace_pipeline_layout);
  if (r == VK_SUCCESS) r = make_pipeline_layout(full_layout, sizeof(FullPush), &full_pipeline_layout);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreatePipelineLayout", r));

  auto make_pool = [&](uint32_t sets, uint32_t buffers_count, uint32_t acceleration_structures, uint32_t images,
                       VkDescriptorPool* out) {
    std::array<VkDescriptorPoolSize, 3> sizes{};
    uint32_t n = 0;
    sizes[n++] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers_count};
    if (acceleration_structures > 0) sizes[n++] = {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, acceleration_structures};
    if (images > 0) sizes[n++] = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, images};
    VkDescriptorPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    info.maxSets = sets;
    info.poolSizeCount = n;
    info.pPoolSizes = sizes.data();
    return vkCreateDescriptorPool(ctx.device, &info, nullptr, out);
  };
  const uint32_t tlas = backend == GpuBackend::ray_tracing_pipeline ? 1 : 0;
  r = make_pool(1, kSceneBindings - 1 - tlas, tlas, kTextureSlots, &scene_pool);
  if (r == VK_SUCCESS) r = make_call_pool(&call_pool);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateDescriptorPool", r));
  return true;
}

// A pool for kCachedSets per-call sets of storage buffers.
VkResult GpuTracer::Impl::make_call_pool(VkDescriptorPool* out) const {
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kCachedSets * kTraceBindings};
  VkDescriptorPoolCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  info.maxSets = kCachedSets;
  info.poolSizeCount = 1;
  info.pPoolSizes = &size;
  return vkCreateDescriptorPool(ctx.device, &info, nullptr, out);
}

// The call pool is full: a new one, the old one kept until no frame in flight
// can use its sets (up to XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS frames are).
bool GpuTracer::Impl::renew_call_pool(std::string* error) {
  VkDescriptorPool fresh = VK_NULL_HANDLE;
  const VkResult r = make_call_pool(&fresh);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateDescriptorPool", r));
  retired_pools.push_back({call_pool, trace_frame_index});
  call_pool = fresh;
  call_sets.clear();
  return true;
}

// A compute pipeline specialised for the tracer's effects and max_depth.
bool GpuTracer::Impl::create_pipeline(const uint32_t* code, size_t bytes, VkPipelineLayout layout, VkPipeline* out,
                                      std::string* error) {
  VkShaderModuleCreateInfo module_info{};
  module_info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  module_info.codeSize = bytes;
  module_info.pCode = code;
  VkShaderModule module = VK_NULL_HANDLE;
  VkResult r = vkCreateShaderModule(ctx.device, &module_info, nullptr, &module);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateShaderModule", r));
  // EFFECTS, MAX_DEPTH (trace_core.glsl), TEXTURE_COUNT, COUNT_WORK (scene_data.glsl; constant_id 3, 4),
  // BVH_STACK (scene_bvh.glsl; constant_id 5).
  const std::array<uint32_t, 5> values = {effects.bits(), static_cast<uint32_t>(options.max_depth), textures.count(),
                                          options.count_work ? 1u : 0u, bvh_stack_entries};
  const std::array<VkSpecializationMapEntry, 5> entries = {
      VkSpecializationMapEntry{0, 0, sizeof(uint32_t)}, VkSpecializationMapEntry{1, sizeof(uint32_t), sizeof(uint32_t)},
      VkSpecializationMapEntry{3, 2 * sizeof(uint32_t), sizeof(uint32_t)},
      VkSpecializationMapEntry{4, 3 * sizeof(uint32_t), sizeof(uint32_t)},
      VkSpecializationMapEntry{5, 4 * sizeof(uint32_t), sizeof(uint32_t)}};
  VkSpecializationInfo spec{};
  spec.mapEntryCount = static_cast<uint32_t>(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = sizeof(values);
  spec.pData = values.data();
  VkComputePipelineCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = &spec;
  info.layout = layout;
  r = vkCreateComputePipelines(ctx.device, VK_NULL_HANDLE, 1, &info, nullptr, out);
  vkDestroyShaderModule(ctx.device, module, nullptr);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateComputePipelines", r));
  return true;
}

// options.backend -> backend: automatic takes the ray-tracing pipeline only
// where the caller enabled it and the device offers it.
bool GpuTracer::Impl::choose_backend(std::string* error) {
  backend = GpuBackend::compute;
  if (options.backend == GpuBackend::compute) return true;
  const RayTracingDeviceSupport support(ctx.physical_device);
  if (options.backend == GpuBackend::automatic) {
    if (ctx.ray_tracing_enabled && support.offered() && ctx.queue != VK_NULL_HANDLE)
      backend = GpuBackend::ray_tracing_pipeline;
  } else if (options.backend == GpuBackend::ray_tracing_pipeline) {
    if (!support.offered())
      return fail(error, "gpu_engine: the ray_tracing_pipeline backend needs " + support.missing() + ", which " +
                             device_name + " does not offer");
    if (!ctx.ray_tracing_enabled)
      return fail(error, "gpu_engine: the ray_tracing_pipeline backend needs " VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME
                         " and " VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME " enabled on the device "
                         "(GpuContext::ray_tracing_enabled is false; see rt_device.hpp)");
    if (ctx.queue == VK_NULL_HANDLE)
      return fail(error, "gpu_engine: the ray_tracing_pipeline backend needs GpuContext::queue to build its "
                         "acceleration structures");
    backend = GpuBackend::ray_tracing_pipeline;
  } else {
    return fail(error, "gpu_engine: unknown backend " + std::to_string(static_cast<int>(options.backend)));
  }
  if (backend == GpuBackend::ray_tracing_pipeline) {
    stages = VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR |
             VK_SHADER_STAGE_ANY_HIT_BIT_KHR;
    push_stage = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    bind_point = VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR;
    pipeline_stage = VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR;
  }
  return true;
}

// Backend, flatten + BVH (+ acceleration structures), upload, scene descriptor set, the trace pipeline.
bool GpuTracer::Impl::create(std::string* error) {
  if (!check_device(error) || !choose_backend(error)) return false;
  ledger = std::make_shared<MemoryLedger>(ctx.physical_device, ctx.device, options.device_local_memory);
  if (ctx.queue == VK_NULL_HANDLE) return fail(error, "gpu_engine: GpuContext::queue is needed to upload the scene");
  SceneData data;
  if (!flatten_scene(scene, &data, error)) return false;
  scene_effects = data.scene_effects;
  effects = scene_effects & options.allowed;
  if (backend == GpuBackend::compute) {
    bvh_node_count = count_bvh_nodes(data.bvh);
    bvh_stack_entries = bvh_inner_levels(data.bvh);
  }
  if (backend == GpuBackend::ray_tracing_pipeline) {
    rt = RtPipelineTracer::create(ctx, ledger, data, error);
    if (rt == nullptr) return false;
  }
  if (!upload_scene(data, error) || !create_layouts(error) || !write_scene_set(error)) return false;
  if (rt)
    return rt->create_pipelines(trace_pipeline_layout, full_pipeline_layout, effects.bits(), options.max_depth,
                                textures.count(), error);
  // The full-render pipeline waits for the first record_full: a foveated app never compiles it.
  return create_pipeline(foveart_gpu_trace_spv, sizeof(foveart_gpu_trace_spv), trace_pipeline_layout, &trace_pipeline,
                         error);
}

// The context names a device, its queue family computes, and the options are in range; the device's limits and name.
bool GpuTracer::Impl::check_device(std::string* error) {
  if (ctx.physical_device == VK_NULL_HANDLE || ctx.device == VK_NULL_HANDLE)
    return fail(error, "gpu_engine: no Vulkan device");
  if (options.max_depth < 0 || options.max_depth > GpuTracerOptions::kMaxDepth)
    return fail(error, "gpu_engine: max_depth " + std::to_string(options.max_depth) + " outside [0, " +
                           std::to_string(GpuTracerOptions::kMaxDepth) + "]");
  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical_device, &family_count, families.data());
  if (ctx.queue_family_index >= family_count ||
      (families[ctx.queue_family_index].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0)
    return fail(error, "gpu_engine: queue family " + std::to_string(ctx.queue_family_index) + " has no compute");
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(ctx.physical_device, &props);
  limits = props.limits;
  device_name = props.deviceName;
  if (limits.maxPerStageDescriptorSamplers < kTextureSlots || limits.maxPerStageDescriptorSampledImages < kTextureSlots ||
      limits.maxDescriptorSetSamplers < kTextureSlots || limits.maxDescriptorSetSampledImages < kTextureSlots)
    return fail(error, "gpu_engine: " + device_name + " binds fewer than " + std::to_string(kTextureSlots) +
                           " sampled textures per shader stage");
  return true;
}

// The scene's storage buffers (binding order), filled through staging; with the
// ray-tracing pipeline no BVH nodes, and the primitives in its acceleration
// structure's order.
bool GpuTracer::Impl::upload_scene(const SceneData& data, std::string* error) {
  struct Upload {
    const void* data;
    size_t bytes;
  };
  const std::vector<uint32_t>& prims = rt ? rt->scene().prims() : data.bvh.prims;
  Uploader uploader(ctx.physical_device, ctx.device, ctx.queue_family_index, ctx.queue);
  if (!textures.create(ledger, uploader, scene, data.texture_slots, error)) return false;
  std::vector<GpuMaterial> materials = data.materials;  // + how each texture is stored
  for (GpuMaterial& m : materials)
    if (m.texture >= 0 && textures.srgb8(static_cast<uint32_t>(m.texture))) m.texture_flags |= kTextureSrgb8;
  const std::array<Upload, kCounterBinding> uploads = {
      rt ? Upload{nullptr, 0} : Upload{data.bvh.nodes.data(), data.bvh.nodes.size() * sizeof(GpuNode)},
      Upload{prims.data(), prims.size() * sizeof(uint32_t)},
      Upload{data.triangles.data(), data.triangles.size() * sizeof(GpuTriangle)},
      Upload{data.shading.data(), data.shading.size() * sizeof(GpuShading)},
      Upload{materials.data(), materials.size() * sizeof(GpuMaterial)},
      Upload{data.lights.data(), data.lights.size() * sizeof(GpuLight)},
      Upload{nullptr, 0},  // kTextureBinding: images
      Upload{&data.globals, sizeof(GpuGlobals)}};
  for (size_t i = 0; i < uploads.size(); ++i) {
    if (i == kTextureBinding) continue;
    if (uploads[i].bytes > limits.maxStorageBufferRange)
      return fail(error, "gpu_engine: scene buffer " + std::to_string(i) + " (" + std::to_string(uploads[i].bytes) +
                             " bytes) exceeds maxStorageBufferRange");
    if (!buffers[i].create(ledger, uploads[i].bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, error) ||
        !uploader.buffer(buffers[i], uploads[i].data, uploads[i].bytes, error))
      return false;
  }
  return uploader.finish(error) &&
         counters.create(ctx.physical_device, ctx.device, kCounterWords * sizeof(uint32_t), nullptr, error) &&  // zeroed
         no_footprints.create(ctx.physical_device, ctx.device, 16, nullptr, error);
}

// The scene's descriptor set: its buffers, binding 0 the TLAS with the ray-tracing pipeline.
bool GpuTracer::Impl::write_scene_set(std::string* error) {
  VkDescriptorSetAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  alloc.descriptorPool = scene_pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &scene_layout;
  const VkResult r = vkAllocateDescriptorSets(ctx.device, &alloc, &scene_set);
  if (r != VK_SUCCESS) return fail(error, vk_error("vkAllocateDescriptorSets", r));
  std::array<VkDescriptorBufferInfo, kSceneBindings> infos{};
  std::array<VkWriteDescriptorSet, kSceneBindings> writes{};
  for (uint32_t i = 0; i < kSceneBindings; ++i) {
    infos[i] = VkDescriptorBufferInfo{i == kCounterBinding ? counters.buffer() : buffers[i].buffer(), 0, VK_WHOLE_SIZE};
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = scene_set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  writes[kTextureBinding].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  writes[kTextureBinding].descriptorCount = kTextureSlots;
  writes[kTextureBinding].pBufferInfo = nullptr;
  writes[kTextureBinding].pImageInfo = textures.descriptors().data();
  VkWriteDescriptorSetAccelerationStructureKHR tlas{};
  VkAccelerationStructureKHR tlas_handle = VK_NULL_HANDLE;
  if (rt) {
    tlas_handle = rt->scene().tlas();
    tlas.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR;
    tlas.accelerationStructureCount = 1;
    tlas.pAccelerationStructures = &tlas_handle;
    writes[0].descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    writes[0].pBufferInfo = nullptr;
    writes[0].pNext = &tlas;
  }
  vkUpdateDescriptorSets(ctx.device, kSceneBindings, writes.data(), 0, nullptr);
  return true;
}

// The cached set for these buffer ranges, or a new one. Updating a found set
// is safe: its buffers are the same frame slot's, whose earlier submission has
// finished (the header's Lifetime clause); a full pool is retired, not reset.
VkDescriptorSet GpuTracer::Impl::call_set(uint64_t kind, VkDescriptorSetLayout layout,
                                          const VkDescriptorBufferInfo* infos, uint32_t count, std::string* error) {
  std::array<uint64_t, 1 + 3 * kTraceBindings> key{};
  key[0] = kind;
  for (uint32_t i = 0; i < count; ++i) {
    key[1 + 3 * i] = handle_bits(infos[i].buffer);
    key[2 + 3 * i] = infos[i].offset;
    key[3 + 3 * i] = infos[i].range;
  }
  VkDescriptorSet set = VK_NULL_HANDLE;
  if (auto it = call_sets.find(key); it != call_sets.end()) {
    set = it->second;
  } else {
    std::erase_if(retired_pools, [&](const RetiredPool& p) {
      const bool done = p.frame_index + XR_FOVEART_DEVICE_TRACE_FRAME_SLOTS <= trace_frame_index;
      if (done) vkDestroyDescriptorPool(ctx.device, p.pool, nullptr);
      return done;
    });
    if (call_sets.size() >= kCachedSets && !renew_call_pool(error)) return VK_NULL_HANDLE;
    VkDescriptorSetAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    alloc.descriptorPool = call_pool;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout;
    const VkResult r = vkAllocateDescriptorSets(ctx.device, &alloc, &set);
    if (r != VK_SUCCESS) {
      fail(error, vk_error("vkAllocateDescriptorSets", r));
      return VK_NULL_HANDLE;
    }
    call_sets.emplace(key, set);
  }
  // Written on every call, found or new: a handle the caller destroyed and
  // created again (same value, same range) must not leave a stale descriptor.
  std::array<VkWriteDescriptorSet, kTraceBindings> writes{};
  for (uint32_t i = 0; i < count; ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = set;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(ctx.device, count, writes.data(), 0, nullptr);
  return set;
}

// A storage-buffer range the device can bind: a buffer, an aligned offset, a size it allows.
bool GpuTracer::Impl::check_range(const char* what, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize size,
                                  VkDeviceSize min_size, std::string* error) const {
  if (buffer == VK_NULL_HANDLE) return fail(error, std::string("gpu_engine: ") + what + ": no buffer");
  if (size < min_size)
    return fail(error, std::string("gpu_engine: ") + what + ": " + std::to_string(size) + " bytes, at least " +
                           std::to_string(min_size) + " needed");
  if (size > limits.maxStorageBufferRange)
    return fail(error, std::string("gpu_engine: ") + what + ": exceeds maxStorageBufferRange");
  const VkDeviceSize align = std::max<VkDeviceSize>(limits.minStorageBufferOffsetAlignment, 1);
  if (offset % align != 0)
    return fail(error, std::string("gpu_engine: ") + what + ": offset " + std::to_string(offset) +
                           " not a multiple of minStorageBufferOffsetAlignment");
  return true;
}

// The ray counters are this tracer's own: order its dispatches' atomics one after another.
void GpuTracer::Impl::barrier_counters(VkCommandBuffer cb) const {
  VkBufferMemoryBarrier b{};
  b.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER;
  b.srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT;
  b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.buffer = counters.buffer();  // kCounterBinding
  b.offset = 0;
  b.size = VK_WHOLE_SIZE;
  vkCmdPipelineBarrier(cb, pipeline_stage, pipeline_stage, 0, 0, nullptr, 1, &b, 0, nullptr);
}

// XrFoveatedDeviceRayBatchFOVEART -> bind, sets, dispatch indirect (64 rays per group) or trace rays
// indirect (the ray-tracing pipeline, where the batch has addresses).
bool GpuTracer::Impl::record_trace(const XrFoveatedDeviceRayBatchFOVEART& batch, std::string* error) {
  if (batch.type != XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART)
    return fail(error, "gpu_engine: batch type is not XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART");
  if (batch.commandBuffer == VK_NULL_HANDLE) return fail(error, "gpu_engine: batch has no command buffer");
  if (!check_range("rayCount", batch.rayCount.buffer, batch.rayCount.offset, batch.rayCount.size,
                   sizeof(uint32_t) * 4, error) ||
      !check_range("rays", batch.rays.buffer, batch.rays.offset, batch.rays.size, 32, error) ||
      !check_range("colors", batch.colors.buffer, batch.colors.offset, batch.colors.size, 16, error))
    return false;
  // The rays' footprints pick the texture level of detail; without them (or an empty range), zeros: level 0.
  const auto* footprint = find_chained<XrFoveatedDeviceRayFootprintFOVEART>(
      batch.next, XR_TYPE_FOVEATED_DEVICE_RAY_FOOTPRINT_FOVEART);
  const auto* addresses = find_chained<XrFoveatedDeviceRayAddressesFOVEART>(
      batch.next, XR_TYPE_FOVEATED_DEVICE_RAY_ADDRESSES_FOVEART);
  last_chain = {footprint != nullptr && footprint->footprints.buffer != VK_NULL_HANDLE,
                addresses != nullptr && addresses->rayCount != 0};
  VkDescriptorBufferInfo footprints{no_footprints.buffer(), 0, VK_WHOLE_SIZE};
  if (options.texture_lod && footprint != nullptr && footprint->footprints.buffer != VK_NULL_HANDLE) {
    if (!check_range("footprints", footprint->footprints.buffer, footprint->footprints.offset,
                     footprint->footprints.size, 4, error))
      return false;
    footprints = {footprint->footprints.buffer, footprint->footprints.offset, footprint->footprints.size};
  }
  const std::array<VkDescriptorBufferInfo, kTraceBindings> infos = {
      VkDescriptorBufferInfo{batch.rayCount.buffer, batch.rayCount.offset, batch.rayCount.size},
      VkDescriptorBufferInfo{batch.rays.buffer, batch.rays.offset, batch.rays.size},
      VkDescriptorBufferInfo{batch.colors.buffer, batch.colors.offset, batch.colors.size}, footprints};
  trace_frame_index = std::max(trace_frame_index, batch.frameIndex);
  const VkDescriptorSet set = call_set(0, trace_layout, infos.data(), kTraceBindings, error);
  if (set == VK_NULL_HANDLE) return false;
  VkCommandBuffer cb = batch.commandBuffer;
  barrier_counters(cb);
  const VkDescriptorSet sets[2] = {scene_set, set};
  if (rt) {
    vkCmdBindDescriptorSets(cb, bind_point, trace_pipeline_layout, 0, 2, sets, 0, nullptr);
    // Only the frame's rays, launched from XrFoveatedDeviceRayCountFOVEART::traceRays at the count's address.
    if (last_chain.addresses && ctx.trace_rays_indirect) {
      return rt->record_indirect(cb, RtPipelineTracer::Entry::trace,
                                 addresses->rayCount + offsetof(XrFoveatedDeviceRayCountFOVEART, traceRays), error);
    }
    // Else one launch per ray the buffers hold; trace.rgen returns past the count.
    const auto launches = static_cast<uint32_t>(std::min<VkDeviceSize>(
        {VkDeviceSize{batch.rayCapacity}, batch.rays.size / 32, batch.colors.size / 16}));
    return rt->record(cb, RtPipelineTracer::Entry::trace, launches, 1, error);
  }
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, trace_pipeline);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, trace_pipeline_layout, 0, 2, sets, 0, nullptr);
  // XrFoveatedDeviceRayCountFOVEART::dispatch64 follows the count.
  vkCmdDispatchIndirect(cb, batch.rayCount.buffer, batch.rayCount.offset + offsetof(XrFoveatedDeviceRayCountFOVEART, dispatch64));
  return true;
}

// engine::render_full on the device: one invocation per pixel, 8 x 8 per group.
bool GpuTracer::Impl::record_full(VkCommandBuffer cb, const FoveartEyeView& view, uint32_t spp, uint64_t seed,
                                  VkBuffer out, VkDeviceSize offset, std::string* error) {
  if (cb == VK_NULL_HANDLE) return fail(error, "gpu_engine: no command buffer");
  if (view.type != FOVEART_TYPE_EYE_VIEW || view.size < sizeof(FoveartEyeView) || view.width_px == 0 ||
      view.height_px == 0)
    return fail(error, "gpu_engine: invalid eye view");
  const uint32_t groups_x = (view.width_px + kFullGroup - 1) / kFullGroup;
  const uint32_t groups_y = (view.height_px + kFullGroup - 1) / kFullGroup;
  if (!rt && (groups_x > limits.maxComputeWorkGroupCount[0] || groups_y > limits.maxComputeWorkGroupCount[1]))
    return fail(error, "gpu_engine: view too large for one dispatch");
  const VkDeviceSize bytes = VkDeviceSize{view.width_px} * view.height_px * 16;
  if (!check_range("full render output", out, offset, bytes, 16, error)) return false;
  if (!rt && full_pipeline == VK_NULL_HANDLE &&
      !create_pipeline(foveart_gpu_full_spv, sizeof(foveart_gpu_full_spv), full_pipeline_layout, &full_pipeline, error))
    return false;
  const VkDescriptorBufferInfo info{out, offset, bytes};
  const VkDescriptorSet set = call_set(1, full_layout, &info, kFullBindings, error);
  if (set == VK_NULL_HANDLE) return false;

  const foveation::EyeFrustum f = foveation::eye_frustum(view);
  const foveation::EyePose pose = foveation::eye_pose(view);
  FullPush push{};
  push.tans[0] = f.tan_left;
  push.tans[1] = f.tan_right;
  push.tans[2] = f.tan_up;
  push.tans[3] = f.tan_down;
  push.position[0] = pose.position_m.x;
  push.position[1] = pose.position_m.y;
  push.position[2] = pose.position_m.z;
  push.orientation[0] = pose.orientation.x;
  push.orientation[1] = pose.orientation.y;
  push.orientation[2] = pose.orientation.z;
  push.orientation[3] = pose.orientation.w;
  push.size_spp_seed[0] = view.width_px;
  push.size_spp_seed[1] = view.height_px;
  push.size_spp_seed[2] = std::max<uint32_t>(spp, 1);  // as render_full: at least one ray
  push.size_spp_seed[3] = static_cast<uint32_t>(seed);
  push.seed_hi[0] = static_cast<uint32_t>(seed >> 32);

  barrier_counters(cb);
  const VkDescriptorSet sets[2] = {scene_set, set};
  if (rt) {
    vkCmdBindDescriptorSets(cb, bind_point, full_pipeline_layout, 0, 2, sets, 0, nullptr);
    vkCmdPushConstants(cb, full_pipeline_layout, push_stage, 0, sizeof(push), &push);
    return rt->record(cb, RtPipelineTracer::Entry::full, view.width_px, view.height_px, error);
  }
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, full_pipeline);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, full_pipeline_layout, 0, 2, sets, 0, nullptr);
  vkCmdPushConstants(cb, full_pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
  vkCmdDispatch(cb, groups_x, groups_y, 1);
  return true;
}

// ---- GpuTracer ---------------------------------------------------------------------

GpuTracer::GpuTracer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GpuTracer::~GpuTracer() = default;

std::unique_ptr<GpuTracer> GpuTracer::create(const GpuContext& context, engine::Scene scene,
                                             const GpuTracerOptions& options, std::string* error) {
  try {
    auto impl = std::make_unique<Impl>();
    impl->ctx = context;
    impl->options = options;
    impl->scene = std::move(scene);
    std::string create_error;
    if (impl->create(&create_error)) return std::unique_ptr<GpuTracer>(new GpuTracer(std::move(impl)));
    if (options.backend != GpuBackend::automatic || impl->backend != GpuBackend::ray_tracing_pipeline) {
      if (error) *error = create_error;
      return nullptr;
    }
    // automatic: a ray-tracing backend that cannot be built gives way to the compute one, with the reason kept.
    auto fallback = std::make_unique<Impl>();
    fallback->ctx = context;
    fallback->options = options;
    fallback->options.backend = GpuBackend::compute;
    fallback->scene = std::move(impl->scene);
    impl.reset();
    if (!fallback->create(error)) return nullptr;
    fallback->backend_fallback = "the ray_tracing_pipeline backend failed (" + create_error + "); compute instead";
    return std::unique_ptr<GpuTracer>(new GpuTracer(std::move(fallback)));
  } catch (const std::exception& e) {
    if (error) *error = std::string("gpu_engine: ") + e.what();
    return nullptr;
  } catch (...) {
    if (error) *error = "gpu_engine: unknown failure";
    return nullptr;
  }
}

bool GpuTracer::record_trace(const XrFoveatedDeviceRayBatchFOVEART& batch, std::string* error) {
  try {
    return impl_->record_trace(batch, error);
  } catch (const std::exception& e) {
    return fail(error, std::string("gpu_engine: ") + e.what());
  }
}

bool GpuTracer::record_full(VkCommandBuffer cb, const FoveartEyeView& view, uint32_t spp, uint64_t seed, VkBuffer out,
                            VkDeviceSize offset, std::string* error) {
  try {
    return impl_->record_full(cb, view, spp, seed, out, offset, error);
  } catch (const std::exception& e) {
    return fail(error, std::string("gpu_engine: ") + e.what());
  }
}

const char* backend_name(GpuBackend backend) {
  switch (backend) {
    case GpuBackend::automatic: return "automatic";
    case GpuBackend::compute: return "compute";
    case GpuBackend::ray_tracing_pipeline: return "ray_tracing_pipeline";
  }
  return "unknown";
}

const engine::Scene& GpuTracer::scene() const { return impl_->scene; }
GpuBackend GpuTracer::backend() const { return impl_->backend; }
const std::string& GpuTracer::backend_fallback() const { return impl_->backend_fallback; }
engine::Effects GpuTracer::scene_effects() const { return impl_->scene_effects; }
engine::Effects GpuTracer::effects() const { return impl_->effects; }

engine::RayCounts GpuTracer::counts() const {
  uint32_t c[4];
  std::memcpy(c, impl_->counters.mapped(), sizeof(c));
  engine::RayCounts out;
  out.primary = c[0];
  out.shadow = c[1];
  out.reflection = c[2];
  out.refraction = c[3];
  return out;
}

WorkCounts GpuTracer::work_counts() const {
  uint32_t c[kCounterWords];
  std::memcpy(c, impl_->counters.mapped(), sizeof(c));
  WorkCounts out;
  out.counted = impl_->options.count_work && impl_->backend == GpuBackend::compute;
  out.bvh_nodes = (uint64_t{c[5]} << 32) | c[4];
  out.triangle_tests = (uint64_t{c[7]} << 32) | c[6];
  return out;
}

uint64_t GpuTracer::bvh_node_count() const { return impl_->bvh_node_count; }
BatchChain GpuTracer::last_batch_chain() const { return impl_->last_chain; }

void GpuTracer::reset_counts() { std::memset(impl_->counters.mapped(), 0, kCounterWords * sizeof(uint32_t)); }

MemoryUse GpuTracer::memory_use() const { return impl_->ledger->use(); }
const std::string& GpuTracer::memory_fallback() const { return impl_->ledger->fallback(); }

}  // namespace foveart::gpu_engine

static_assert(std::is_same_v<decltype(&foveart_gpu_engine_trace_rays_device), PFN_xrFoveatedTraceRaysDeviceFOVEART>,
              "the C entry point is the layer's device trace callback");

extern "C" XrResult foveart_gpu_engine_trace_rays_device(void* user_data, const XrFoveatedDeviceRayBatchFOVEART* batch) {
  if (user_data == nullptr || batch == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  auto* tracer = static_cast<foveart::gpu_engine::GpuTracer*>(user_data);
  std::string error;
  if (batch->type != XR_TYPE_FOVEATED_DEVICE_RAY_BATCH_FOVEART || batch->commandBuffer == VK_NULL_HANDLE ||
      batch->rayCount.buffer == VK_NULL_HANDLE || batch->rays.buffer == VK_NULL_HANDLE ||
      batch->colors.buffer == VK_NULL_HANDLE)
    return XR_ERROR_VALIDATION_FAILURE;
  return tracer->record_trace(*batch, &error) ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}
