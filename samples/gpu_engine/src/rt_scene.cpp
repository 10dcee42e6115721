// RtScene: the BLAS and TLAS built once with vkCmdBuildAccelerationStructuresKHR
// on the device, from input buffers freed after the build: the vertices in
// device-local memory (filled through staging), the one TLAS instance in
// host-visible memory (64 bytes the host writes once, read by one build).
#include "rt_scene.hpp"
#include "command_slot.hpp"
#include "vk_helpers.hpp"

#include "rt_layout.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

namespace foveart::gpu_engine {
namespace {

constexpr uint64_t kBuildTimeoutNs = 60ull * 1000 * 1000 * 1000;
constexpr VkBufferUsageFlags kBuildInput =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkBufferUsageFlags kStorage =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
constexpr VkBufferUsageFlags kScratch = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

VkPhysicalDeviceAccelerationStructurePropertiesKHR acceleration_structure_properties(const GpuContext& ctx) {
  VkPhysicalDeviceAccelerationStructurePropertiesKHR as_props{};
  as_props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR;
  VkPhysicalDeviceProperties2 props{};
  props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  props.pNext = &as_props;
  vkGetPhysicalDeviceProperties2(ctx.physical_device, &props);
  as_props.pNext = nullptr;  // props is gone
  return as_props;
}

}  // namespace

std::unique_ptr<RtScene> RtScene::create(const GpuContext& context, const RtFunctions& functions,
                                         const std::shared_ptr<MemoryLedger>& ledger, const SceneData& data,
                                         std::string* error) {
  std::unique_ptr<RtScene> scene(new RtScene());
  scene->ledger_ = ledger;
  scene->device_ = context.device;
  scene->fn_ = &functions;
  if (!scene->build(context, data, error)) return nullptr;
  return scene;
}

RtScene::~RtScene() {
  if (fn_ == nullptr) return;
  if (tlas_ != VK_NULL_HANDLE) fn_->destroy_acceleration_structure(device_, tlas_, nullptr);
  if (blas_ != VK_NULL_HANDLE) fn_->destroy_acceleration_structure(device_, blas_, nullptr);
  tlas_storage_.destroy();
  blas_storage_.destroy();
}

// One build's inputs and the buffers that must outlive its commands.
struct RtScene::Build {
  Build(const GpuContext& context, VkDeviceSize align, std::string* error_out)
      : ctx(context), scratch_align(align), error(error_out) {}
  const GpuContext& ctx;
  VkDeviceSize scratch_align;
  std::string* error;
  VkCommandBuffer cb = VK_NULL_HANDLE;
  VkDeviceAddress vertex_address = 0;
  DeviceBuffer vertex_buffer, blas_scratch, tlas_scratch;
  MappedBuffer instance_buffer;
};

bool RtScene::build(const GpuContext& ctx, const SceneData& data, std::string* error) {
  const VkPhysicalDeviceAccelerationStructurePropertiesKHR as_props = acceleration_structure_properties(ctx);
  RtPrimitiveOrder order = order_rt_primitives(data.bvh.prims, data.triangles);
  prims_ = std::move(order.prims);
  geometry1_first_ = order.geometry1_first;
  if (static_cast<uint64_t>(prims_.size()) > as_props.maxPrimitiveCount)
    return fail(error, "gpu_engine: " + std::to_string(prims_.size()) +
                           " triangles exceed the device's maxPrimitiveCount for one acceleration structure");
  Build b(ctx, std::max<VkDeviceSize>(as_props.minAccelerationStructureScratchOffsetAlignment, 1), error);
  if (!upload_vertices(b, data)) return false;
  CommandSlot commands;
  if (!commands.create(device_, ctx.queue_family_index, error) || !commands.begin(error)) return false;
  b.cb = commands.cb();
  if (!build_blas(b) || !build_tlas(b)) return false;
  return commands.submit_and_wait(ctx.queue, kBuildTimeoutNs, "acceleration structure build", error);
}

// Three world-space vertices per primitive, in prims_ order, into a build input buffer.
bool RtScene::upload_vertices(Build& b, const SceneData& data) {
  std::vector<float> vertices;
  vertices.reserve(prims_.size() * 9);
  for (uint32_t t : prims_) {
    const GpuTriangle& g = data.triangles[t];
    vertices.insert(vertices.end(), {g.p0[0], g.p0[1], g.p0[2], g.p1[0], g.p1[1], g.p1[2], g.p2[0], g.p2[1], g.p2[2]});
  }
  const VkDeviceSize bytes = vertices.size() * sizeof(float);
  Uploader uploader(b.ctx.physical_device, device_, b.ctx.queue_family_index, b.ctx.queue);
  if (!b.vertex_buffer.create(ledger_, bytes, kBuildInput, b.error) ||
      !uploader.buffer(b.vertex_buffer, vertices.data(), bytes, b.error) || !uploader.finish(b.error))
    return false;
  b.vertex_address = fn_->address(device_, b.vertex_buffer.buffer());
  return true;
}

// An acceleration structure of `type` for `info`: its storage and scratch
// buffers, the structure, and info's destination and scratch address set.
bool RtScene::create_structure(Build& b, VkAccelerationStructureTypeKHR type,
                               VkAccelerationStructureBuildGeometryInfoKHR* info, const uint32_t* max_counts,
                               DeviceBuffer* storage, DeviceBuffer* scratch, VkAccelerationStructureKHR* out) {
  const RtFunctions& fn = *fn_;
  VkAccelerationStructureBuildSizesInfoKHR sizes{};
  sizes.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR;
  fn.get_acceleration_structure_build_sizes(device_, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, info, max_counts,
                                            &sizes);
  if (!storage->create(ledger_, sizes.accelerationStructureSize, kStorage, b.error) ||
      !scratch->create(ledger_, sizes.buildScratchSize + b.scratch_align, kScratch, b.error))
    return false;
  VkAccelerationStructureCreateInfoKHR create{};
  create.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR;
  create.buffer = storage->buffer();
  create.size = sizes.accelerationStructureSize;
  create.type = type;
  const VkResult r = fn.create_acceleration_structure(device_, &create, nullptr, out);
  if (r != VK_SUCCESS) {
    *out = VK_NULL_HANDLE;
    return fail(b.error, vk_error("vkCreateAccelerationStructureKHR", r));
  }
  info->dstAccelerationStructure = *out;
  info->scratchData.deviceAddress = align_up(fn.address(device_, scratch->buffer()), b.scratch_align);
  return true;
}

// The BLAS: one geometry per non-empty kind (opaque, then alpha-tested); none without triangles.
bool RtScene::build_blas(Build& b) {
  const uint32_t counts[2] = {geometry1_first_, static_cast<uint32_t>(prims_.size()) - geometry1_first_};
  std::vector<VkAccelerationStructureGeometryKHR> geometries;
  std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
  std::vector<uint32_t> max_primitives;
  uint32_t first = 0;
  for (uint32_t kind = 0; kind < 2; ++kind) {
    if (counts[kind] == 0) continue;
    VkAccelerationStructureGeometryKHR g{};
    g.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.flags = kind == 0 ? VK_GEOMETRY_OPAQUE_BIT_KHR : 0;
    g.geometry.triangles.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
    g.geometry.triangles.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    g.geometry.triangles.vertexData.deviceAddress = b.vertex_address + VkDeviceAddress{first} * 9 * sizeof(float);
    g.geometry.triangles.vertexStride = 3 * sizeof(float);
    g.geometry.triangles.maxVertex = 3 * counts[kind] - 1;
    g.geometry.triangles.indexType = VK_INDEX_TYPE_NONE_KHR;
    geometries.push_back(g);
    ranges.push_back(VkAccelerationStructureBuildRangeInfoKHR{counts[kind], 0, 0, 0});
    max_primitives.push_back(counts[kind]);
    first += counts[kind];
  }
  if (geometries.empty()) return true;
  VkAccelerationStructureBuildGeometryInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
  info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = static_cast<uint32_t>(geometries.size());
  info.pGeometries = geometries.data();
  if (!create_structure(b, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &info, max_primitives.data(),
                        &blas_storage_, &b.blas_scratch, &blas_))
    return false;
  const VkAccelerationStructureBuildRangeInfoKHR* range_list = ranges.data();
  fn_->cmd_build_acceleration_structures(b.cb, 1, &info, &range_list);
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  barrier.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
  vkCmdPipelineBarrier(b.cb, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &barrier, 0, nullptr, 0, nullptr);
  return true;
}

// The TLAS: one instance of the BLAS (none if there is no BLAS), identity transform.
bool RtScene::build_tlas(Build& b) {
  const RtFunctions& fn = *fn_;
  VkAccelerationStructureInstanceKHR instance{};
  instance.transform.matrix[0][0] = instance.transform.matrix[1][1] = instance.transform.matrix[2][2] = 1.0f;
  instance.mask = 0xFF;
  instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
  const uint32_t instances = blas_ != VK_NULL_HANDLE ? 1u : 0u;
  if (instances == 1) {
    VkAccelerationStructureDeviceAddressInfoKHR address{};
    address.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR;
    address.accelerationStructure = blas_;
    instance.accelerationStructureReference = fn.get_acceleration_structure_device_address(device_, &address);
  }
  if (!b.instance_buffer.create(b.ctx.physical_device, device_, sizeof(instance), &instance, b.error, kBuildInput))
    return false;
  VkAccelerationStructureGeometryKHR tlas_geometry{};
  tlas_geometry.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR;
  tlas_geometry.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  tlas_geometry.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  tlas_geometry.geometry.instances.arrayOfPointers = VK_FALSE;
  tlas_geometry.geometry.instances.data.deviceAddress = fn.address(device_, b.instance_buffer.buffer());
  VkAccelerationStructureBuildGeometryInfoKHR info{};
  info.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR;
  info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = 1;
  info.pGeometries = &tlas_geometry;
  if (!create_structure(b, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &info, &instances, &tlas_storage_,
                        &b.tlas_scratch, &tlas_))
    return false;
  const VkAccelerationStructureBuildRangeInfoKHR tlas_range{instances, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* tlas_ranges = &tlas_range;
  fn.cmd_build_acceleration_structures(b.cb, 1, &info, &tlas_ranges);
  // The traces of later submissions on this queue read the TLAS (and through it the BLAS).
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  barrier.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
  vkCmdPipelineBarrier(b.cb, VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                       VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR, 0, 1, &barrier, 0, nullptr, 0, nullptr);
  return true;
}

}  // namespace foveart::gpu_engine
