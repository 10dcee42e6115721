// RtPipelineTracer: shader modules -> vkCreateRayTracingPipelinesKHR -> group
// handles copied into a binding table laid out by shaderGroupHandleSize,
// shaderGroupHandleAlignment and shaderGroupBaseAlignment -> vkCmdTraceRaysKHR.
#include "rt_pipeline_tracer.hpp"
#include "vk_helpers.hpp"

#include "rt_layout.hpp"

#include <gpu_engine_shaders/rt_alpha.spv.h>
#include <gpu_engine_shaders/rt_full.spv.h>
#include <gpu_engine_shaders/rt_hit.spv.h>
#include <gpu_engine_shaders/rt_miss.spv.h>
#include <gpu_engine_shaders/rt_shadow.spv.h>
#include <gpu_engine_shaders/rt_trace.spv.h>

#include <algorithm>
#include <cstring>
#include <vector>

namespace foveart::gpu_engine {
namespace {

// Shader groups of each pipeline, in binding-table order.
constexpr uint32_t kGroupRaygen = 0;
constexpr uint32_t kGroupMiss = 1;     // rt_miss.rmiss (closest-hit queries)
constexpr uint32_t kGroupShadow = 2;   // rt_shadow.rmiss (occlusion queries)
constexpr uint32_t kGroupHit = 3;      // rt_hit.rchit + rt_alpha.rahit
constexpr uint32_t kGroupCount = 4;

// Shader modules destroyed on scope exit.
struct Modules {
  VkDevice device = VK_NULL_HANDLE;
  std::vector<VkShaderModule> modules;
  explicit Modules(VkDevice d) : device(d) {}
  Modules(const Modules&) = delete;
  Modules& operator=(const Modules&) = delete;
  ~Modules() {
    for (VkShaderModule m : modules) vkDestroyShaderModule(device, m, nullptr);
  }
  bool add(const uint32_t* code, size_t bytes, std::string* error) {
    VkShaderModuleCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    info.codeSize = bytes;
    info.pCode = code;
    VkShaderModule m = VK_NULL_HANDLE;
    const VkResult r = vkCreateShaderModule(device, &info, nullptr, &m);
    if (r != VK_SUCCESS) return fail(error, vk_error("vkCreateShaderModule (ray tracing)", r));
    modules.push_back(m);
    return true;
  }
};

// The shader groups, in binding-table order: raygen, miss, shadow miss (general
// groups of stages 0..2), then the hit group (closest hit 3, any hit 4).
std::array<VkRayTracingShaderGroupCreateInfoKHR, kGroupCount> shader_groups() {
  std::array<VkRayTracingShaderGroupCreateInfoKHR, kGroupCount> groups{};
  for (uint32_t i = 0; i < kGroupCount; ++i) {
    groups[i].sType = VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR;
    groups[i].type = VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR;
    groups[i].generalShader = i;  // stages 0..2: raygen, miss, shadow miss
    groups[i].closestHitShader = VK_SHADER_UNUSED_KHR;
    groups[i].anyHitShader = VK_SHADER_UNUSED_KHR;
    groups[i].intersectionShader = VK_SHADER_UNUSED_KHR;
  }
  groups[kGroupHit].type = VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR;
  groups[kGroupHit].generalShader = VK_SHADER_UNUSED_KHR;
  groups[kGroupHit].closestHitShader = 3;
  groups[kGroupHit].anyHitShader = 4;
  return groups;
}

}  // namespace

std::unique_ptr<RtPipelineTracer> RtPipelineTracer::create(const GpuContext& context,
                                                           const std::shared_ptr<MemoryLedger>& ledger,
                                                           const SceneData& data, std::string* error) {
  std::unique_ptr<RtPipelineTracer> t(new RtPipelineTracer());
  t->ctx_ = context;
  t->ledger_ = ledger;
  if (!t->fn_.load(context.device, error)) return nullptr;
  t->props_.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR;
  VkPhysicalDeviceProperties2 props{};
  props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  props.pNext = &t->props_;
  vkGetPhysicalDeviceProperties2(context.physical_device, &props);
  t->limits_ = props.properties.limits;
  if (t->props_.maxRayRecursionDepth < 1) {
    fail(error, "gpu_engine: the device's maxRayRecursionDepth is 0");
    return nullptr;
  }
  t->scene_ = RtScene::create(context, t->fn_, ledger, data, error);
  if (t->scene_ == nullptr) return nullptr;
  return t;
}

RtPipelineTracer::~RtPipelineTracer() {
  for (Table& table : tables_) {
    if (table.pipeline != VK_NULL_HANDLE) vkDestroyPipeline(ctx_.device, table.pipeline, nullptr);
    table.buffer.destroy();
  }
  scene_.reset();  // before fn_ (which it points at) goes
}

bool RtPipelineTracer::create_pipelines(VkPipelineLayout trace_layout, VkPipelineLayout full_layout,
                                        uint32_t effect_bits, int max_depth, uint32_t texture_count,
                                        std::string* error) {
  texture_count_ = texture_count;
  return create_pipeline(Entry::trace, trace_layout, effect_bits, max_depth, error) &&
         create_pipeline(Entry::full, full_layout, effect_bits, max_depth, error);
}

bool RtPipelineTracer::create_pipeline(Entry entry, VkPipelineLayout layout, uint32_t effect_bits, int max_depth,
                                       std::string* error) {
  Modules modules(ctx_.device);
  const bool ok = entry == Entry::trace ? modules.add(foveart_gpu_rt_trace_spv, sizeof(foveart_gpu_rt_trace_spv), error)
                                        : modules.add(foveart_gpu_rt_full_spv, sizeof(foveart_gpu_rt_full_spv), error);
  if (!ok || !modules.add(foveart_gpu_rt_miss_spv, sizeof(foveart_gpu_rt_miss_spv), error) ||
      !modules.add(foveart_gpu_rt_shadow_spv, sizeof(foveart_gpu_rt_shadow_spv), error) ||
      !modules.add(foveart_gpu_rt_hit_spv, sizeof(foveart_gpu_rt_hit_spv), error) ||
      !modules.add(foveart_gpu_rt_alpha_spv, sizeof(foveart_gpu_rt_alpha_spv), error))
    return false;

  const std::array<uint32_t, 4> values = {effect_bits, static_cast<uint32_t>(max_depth), scene_->geometry1_first(),
                                          texture_count_};
  std::array<VkSpecializationMapEntry, 4> entries{};
  for (uint32_t i = 0; i < entries.size(); ++i)
    entries[i] = VkSpecializationMapEntry{i, static_cast<uint32_t>(i * sizeof(uint32_t)), sizeof(uint32_t)};
  VkSpecializationInfo spec{};
  spec.mapEntryCount = static_cast<uint32_t>(entries.size());
  spec.pMapEntries = entries.data();
  spec.dataSize = sizeof(values);
  spec.pData = values.data();

  const VkShaderStageFlagBits stage_bits[5] = {VK_SHADER_STAGE_RAYGEN_BIT_KHR, VK_SHADER_STAGE_MISS_BIT_KHR,
                                               VK_SHADER_STAGE_MISS_BIT_KHR, VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR,
                                               VK_SHADER_STAGE_ANY_HIT_BIT_KHR};
  std::array<VkPipelineShaderStageCreateInfo, 5> stages{};
  for (uint32_t i = 0; i < stages.size(); ++i) {
    stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[i].stage = stage_bits[i];
    stages[i].module = modules.modules[i];
    stages[i].pName = "main";
    stages[i].pSpecializationInfo = &spec;
  }
  const std::array<VkRayTracingShaderGroupCreateInfoKHR, kGroupCount> groups = shader_groups();

  VkRayTracingPipelineCreateInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR;
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.groupCount = kGroupCount;
  info.pGroups = groups.data();
  info.maxPipelineRayRecursionDepth = 1;  // rays are traced from the ray-generation shader only
  info.layout = layout;
  Table& table = tables_[static_cast<size_t>(entry)];
  const VkResult r =
      fn_.create_ray_tracing_pipelines(ctx_.device, VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &info, nullptr, &table.pipeline);
  if (r != VK_SUCCESS) {
    table.pipeline = VK_NULL_HANDLE;
    return fail(error, vk_error("vkCreateRayTracingPipelinesKHR", r));
  }
  return fill_binding_table(table, error);
}

// The binding table: raygen | miss, shadow miss | hit group, each region at a
// multiple of shaderGroupBaseAlignment, records shaderGroupHandleAlignment apart.
bool RtPipelineTracer::fill_binding_table(Table& table, std::string* error) {
  const uint32_t handle_bytes = props_.shaderGroupHandleSize;
  std::vector<uint8_t> handles(size_t{kGroupCount} * handle_bytes);
  const VkResult r = fn_.get_ray_tracing_shader_group_handles(ctx_.device, table.pipeline, 0, kGroupCount,
                                                              handles.size(), handles.data());
  if (r != VK_SUCCESS) return fail(error, vk_error("vkGetRayTracingShaderGroupHandlesKHR", r));
  const BindingTableLayout layout_bytes = binding_table_layout(handle_bytes, props_.shaderGroupHandleAlignment,
                                                               props_.shaderGroupBaseAlignment);
  const VkDeviceSize record_stride = layout_bytes.record_stride_bytes;
  const VkDeviceSize base_align = std::max<uint32_t>(props_.shaderGroupBaseAlignment, 1);
  const VkDeviceSize raygen_offset = layout_bytes.raygen_offset_bytes;
  const VkDeviceSize miss_offset = layout_bytes.miss_offset_bytes;
  const VkDeviceSize hit_offset = layout_bytes.hit_offset_bytes;
  const VkDeviceSize table_bytes = layout_bytes.table_bytes;
  // Device-local, read by every launch; filled through staging.
  if (!table.buffer.create(ledger_, table_bytes + base_align,
                           VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, error))
    return false;
  const VkDeviceAddress buffer_address = fn_.address(ctx_.device, table.buffer.buffer());
  const VkDeviceAddress base = align_up(buffer_address, base_align);
  std::vector<uint8_t> host(static_cast<size_t>(table.buffer.size()), 0);
  uint8_t* bytes = host.data() + (base - buffer_address);
  auto put = [&](VkDeviceSize offset, uint32_t group) {
    std::memcpy(bytes + offset, handles.data() + size_t{group} * handle_bytes, handle_bytes);
  };
  put(raygen_offset, kGroupRaygen);
  put(miss_offset, kGroupMiss);
  put(miss_offset + record_stride, kGroupShadow);
  put(hit_offset, kGroupHit);
  Uploader uploader(ctx_.physical_device, ctx_.device, ctx_.queue_family_index, ctx_.queue);
  if (!uploader.buffer(table.buffer, host.data(), host.size(), error) || !uploader.finish(error)) return false;
  table.raygen = VkStridedDeviceAddressRegionKHR{base + raygen_offset, record_stride, record_stride};
  table.miss = VkStridedDeviceAddressRegionKHR{base + miss_offset, record_stride, 2 * record_stride};
  table.hit = VkStridedDeviceAddressRegionKHR{base + hit_offset, record_stride, record_stride};
  table.callable = VkStridedDeviceAddressRegionKHR{0, 0, 0};
  if (record_stride > props_.maxShaderGroupStride)
    return fail(error, "gpu_engine: shader binding table stride exceeds maxShaderGroupStride");
  return true;
}

bool RtPipelineTracer::record(VkCommandBuffer cb, Entry entry, uint32_t width, uint32_t height,
                              std::string* error) const {
  const Table& table = tables_[static_cast<size_t>(entry)];
  if (table.pipeline == VK_NULL_HANDLE) return fail(error, "gpu_engine: ray-tracing pipeline not created");
  const uint64_t max_x = uint64_t{limits_.maxComputeWorkGroupCount[0]} * limits_.maxComputeWorkGroupSize[0];
  const uint64_t max_y = uint64_t{limits_.maxComputeWorkGroupCount[1]} * limits_.maxComputeWorkGroupSize[1];
  if (width > max_x || height > max_y || uint64_t{width} * height > props_.maxRayDispatchInvocationCount)
    return fail(error, "gpu_engine: " + std::to_string(width) + " x " + std::to_string(height) +
                           " rays exceed the device's limits for one vkCmdTraceRaysKHR");
  if (width == 0 || height == 0) return true;
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, table.pipeline);
  fn_.cmd_trace_rays(cb, &table.raygen, &table.miss, &table.hit, &table.callable, width, height, 1);
  return true;
}

bool RtPipelineTracer::record_indirect(VkCommandBuffer cb, Entry entry, VkDeviceAddress args,
                                       std::string* error) const {
  const Table& table = tables_[static_cast<size_t>(entry)];
  if (table.pipeline == VK_NULL_HANDLE) return fail(error, "gpu_engine: ray-tracing pipeline not created");
  if (fn_.cmd_trace_rays_indirect == nullptr) return fail(error, "gpu_engine: no vkCmdTraceRaysIndirectKHR");
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, table.pipeline);
  fn_.cmd_trace_rays_indirect(cb, &table.raygen, &table.miss, &table.hit, &table.callable, args);
  return true;
}

}  // namespace foveart::gpu_engine
