// The device-trace tests' harness (device_trace_test.cpp,
// device_ray_cache_test.cpp): a small view's tables, a view looking along
// (1, 1, 1), a test "engine" that answers on the device (a fill pattern, each
// ray's direction through direction_engine.comp, a sky of stripes through
// stripes_engine.comp, an error, or nothing), the
// CPU callbacks that answer alike, and a fixture with lavapipe under
// validation, a reconstructor, the tables on the device and one eye.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "direction_engine.spv.h"
#include "stripes_engine.spv.h"
#include "foveation/display_model.hpp"
#include "foveation/foveated_view.hpp"
#include "foveation/visible_points.hpp"
#include "gpu/reconstructor.hpp"
#include "gpu/shader_interface/device_trace.h"
#include "gpu/vk_util.hpp"
#include "headless_vulkan.hpp"
#include "icd_pin.h"

namespace foveart::gpu::device_test {

using layer::DevicePreference;
using layer::HeadlessVulkan;

inline constexpr uint32_t kViewW = 96;
inline constexpr uint32_t kViewH = 80;
inline constexpr uint32_t kRaysPerPoint = 2;

// The tables of a width x height view of 60 degrees (seed 1), built once per caller's static.
inline std::shared_ptr<const foveation::ViewTables> view_tables(uint32_t width_px, uint32_t height_px, double scale,
                                                               foveation::InterpMethod method, int k) {
  foveation::PointSetKey key;
  key.display = foveation::DisplayModel::from_fov(width_px, height_px, 60.0);
  key.display.scale = scale;
  key.seed = 1;
  foveation::InterpOptions o;
  o.method = method;
  o.k = k;
  foveation::Executor executor(2);
  return foveation::load_view_tables(std::nullopt, key, o, executor);
}

// Scale 6: the pixel grid's edge lies inside the view, so frames hold grid and disc points.
inline std::shared_ptr<const foveation::ViewTables> small_tables() {
  static const auto tables = view_tables(kViewW, kViewH, 6.0, foveation::InterpMethod::msm, 5);
  return tables;
}

// A view wide enough that the device compaction's scan of the block sums loops:
// more than 4 x FOVEART_DEVICE_RAYS_BLOCK blocks (scan.glsl takes 4 per invocation).
// Nearest-neighbour tables, the cheapest to build: only the points matter here.
inline constexpr uint32_t kWideViewW = 224;
inline constexpr uint32_t kWideViewH = 192;
inline std::shared_ptr<const foveation::ViewTables> wide_tables() {
  static const auto tables = view_tables(kWideViewW, kWideViewH, 1.0, foveation::InterpMethod::nearest, 1);
  return tables;
}

// The eye looks along (1, 1, 1): every ray direction of its 60-degree frustum
// has positive components, so a direction is a valid colour (the "direction" engines).
inline foveation::FrameRequest request(glm::vec2 gaze_px, uint64_t frame_index,
                                       glm::uvec2 size_px = glm::uvec2(kViewW, kViewH)) {
  foveation::FrameRequest r;
  foveation::EyePose pose;
  pose.position_m = {-0.032f, 1.6f, 0.25f};
  const glm::vec3 forward(0.0f, 0.0f, -1.0f), diagonal = glm::normalize(glm::vec3(1.0f));
  pose.orientation = glm::angleAxis(std::acos(glm::dot(forward, diagonal)), glm::normalize(glm::cross(forward, diagonal)));
  r.view = foveation::make_eye_view(0, size_px.x, size_px.y, pose, -0.4f, 0.42f, 0.38f, -0.36f);
  r.frame_index = frame_index;
  r.gaze_px = gaze_px;
  return r;
}

inline constexpr float kConstant = 0.25f;

inline int32_t constant_colour(void*, const FoveartRayBatch* batch) {
  std::fill_n(batch->out_rgb, std::size_t(batch->ray_count) * 3, kConstant);
  return FOVEART_RESULT_SUCCESS;
}

// Colour = the ray's direction, depth = its screen y: a colour that varies from ray to ray.
inline int32_t direction_colour(void*, const FoveartRayBatch* batch) {
  std::copy_n(batch->directions, std::size_t(batch->ray_count) * 3, batch->out_rgb);
  for (uint32_t i = 0; i < batch->ray_count; ++i) batch->out_depth_m[i] = batch->sample_px[2 * i + 1];
  return FOVEART_RESULT_SUCCESS;
}

// A device "engine" for the tests: it answers with a fill pattern (or an
// error, or nothing) and may copy what the layer handed it to the host.
struct TestEngine {
  // fill: fill_bits everywhere; direction: each ray's (direction, screen y) as
  // its (colour, depth), copied; stripes: a sky of stripes fixed in the world
  // (stripes_engine.comp); error: an error; nothing: records nothing.
  enum class Answer { fill, direction, stripes, error, nothing };
  Answer answer = Answer::fill;
  uint32_t fill_bits = 0;  // the colour buffer's every word (rgb and depth)
  bool copy = false;       // copy rays, point indices and counts into the buffers below (any answer but error, nothing)
  VkDevice device = VK_NULL_HANDLE;
  const VkPhysicalDeviceMemoryProperties* memory = nullptr;
  BoundBuffer rays, point_index, control, footprints;
  uint32_t calls = 0;
  DeviceRayBatch last{};

  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE, stripes_pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;

  ~TestEngine() {
    for (BoundBuffer* b : {&rays, &point_index, &control, &footprints}) destroy_buffer(device, b);
    for (VkPipeline p : {pipeline, stripes_pipeline})
      if (p != VK_NULL_HANDLE) vkDestroyPipeline(device, p, nullptr);
    if (layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(device, layout, nullptr);
    if (set_layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (pool != VK_NULL_HANDLE) vkDestroyDescriptorPool(device, pool, nullptr);
  }
  // direction_engine.comp (or stripes_engine.comp) over the batch, dispatched from the layer's counts.
  bool engine_shader(const DeviceRayBatch& batch, bool stripes) {
    static constexpr uint32_t kOnes[3] = {1, 1, 1};
    std::string error;
    if (pipeline == VK_NULL_HANDLE) {
      const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3};
      auto pool_info = vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
      pool_info.maxSets = 1;
      pool_info.poolSizeCount = 1;
      pool_info.pPoolSizes = &size;
      if (!create_storage_pipeline_layout(device, kOnes, 3, 4, &set_layout, &layout, &error) ||
          !create_compute_pipeline(device, layout, direction_engine_spv, sizeof direction_engine_spv, &pipeline,
                                   &error) ||
          !create_compute_pipeline(device, layout, stripes_engine_spv, sizeof stripes_engine_spv, &stripes_pipeline,
                                   &error) ||
          vkCreateDescriptorPool(device, &pool_info, nullptr, &pool) != VK_SUCCESS) {
        return false;
      }
      auto alloc = vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
      alloc.descriptorPool = pool;
      alloc.descriptorSetCount = 1;
      alloc.pSetLayouts = &set_layout;
      if (vkAllocateDescriptorSets(device, &alloc, &set) != VK_SUCCESS) return false;
    }
    const VkDescriptorBufferInfo buffers[3] = {{batch.ray_count.buffer, batch.ray_count.offset, 4},
                                               {batch.rays.buffer, batch.rays.offset, batch.rays.size},
                                               {batch.colors.buffer, batch.colors.offset, batch.colors.size}};
    write_storage_descriptors(device, set, buffers, kOnes, 3);
    vkCmdBindPipeline(batch.command_buffer, VK_PIPELINE_BIND_POINT_COMPUTE, stripes ? stripes_pipeline : pipeline);
    vkCmdBindDescriptorSets(batch.command_buffer, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
    vkCmdDispatchIndirect(batch.command_buffer, batch.ray_count.buffer, batch.ray_count.offset + 4);
    return true;
  }
  bool readback(BoundBuffer& b, const BufferRange& from, VkCommandBuffer cb) {
    if (b.buffer == VK_NULL_HANDLE) {
      std::string error;
      b.size = from.size;
      if (!create_bound_buffer(device, *memory, from.size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, buffer_memory_flags(true),
                               &b.buffer, &b.memory, &b.mapped, &error)) {
        return false;
      }
    }
    const VkBufferCopy region{from.offset, 0, std::min(from.size, b.size)};
    vkCmdCopyBuffer(cb, from.buffer, b.buffer, 1, &region);
    return true;
  }
};

inline bool test_engine(TestEngine* engine, const DeviceRayBatch* batch) {
  ++engine->calls;
  engine->last = *batch;
  if (engine->answer == TestEngine::Answer::error) return false;
  if (engine->answer == TestEngine::Answer::nothing) return true;
  VkCommandBuffer cb = batch->command_buffer;
  if (engine->answer == TestEngine::Answer::direction || engine->answer == TestEngine::Answer::stripes) {
    if (!engine->engine_shader(*batch, engine->answer == TestEngine::Answer::stripes)) return false;
  } else {
    vkCmdFillBuffer(cb, batch->colors.buffer, batch->colors.offset, batch->colors.size, engine->fill_bits);
  }
  if (engine->copy && (!engine->readback(engine->rays, batch->rays, cb) ||
                       !engine->readback(engine->point_index, batch->point_index, cb) ||
                       !engine->readback(engine->control, batch->ray_count, cb) ||
                       !engine->readback(engine->footprints, batch->footprints, cb))) {
    return false;
  }
  if (engine->copy) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_TRANSFER_WRITE_BIT,
                            VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr,
                         0, nullptr);
  }
  return true;
}

inline uint32_t bits_of(float f) {
  uint32_t b = 0;
  std::memcpy(&b, &f, 4);
  return b;
}

class DeviceTraceFixture : public ::testing::Test {
 protected:
  static void TearDownTestSuite() {
    vulkan_.reset();
    addressed_vulkan_.reset();
  }
  // The device enables bufferDeviceAddress (VK_KHR_buffer_device_address, as an app
  // through xrCreateVulkanDeviceKHR) and the reconstructor is told so.
  virtual bool buffer_device_address() const { return false; }
  static std::unique_ptr<HeadlessVulkan> make_vulkan(bool addresses) {
    if (!addresses) return std::make_unique<HeadlessVulkan>(DevicePreference::cpu, true);
    return std::make_unique<HeadlessVulkan>(DevicePreference::cpu, true, [](VkPhysicalDevice, VkDeviceCreateInfo* info) {
      static VkPhysicalDeviceBufferDeviceAddressFeatures features{
          VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES, nullptr, VK_TRUE, VK_FALSE, VK_FALSE};
      static const char* extensions[] = {VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME};
      info->pNext = &features;
      info->enabledExtensionCount = 1;
      info->ppEnabledExtensionNames = extensions;
    });
  }
  void SetUp() override {
    std::unique_ptr<HeadlessVulkan>& slot = buffer_device_address() ? addressed_vulkan_ : vulkan_;
    if (slot == nullptr) {
      slot = make_vulkan(buffer_device_address());
      sim::pin_loaded_vulkan_icds_and_layers();  // LeakSanitizer names them at exit (icd_pin.h)
    }
    vulkan_in_use_ = slot.get();
    ASSERT_TRUE(slot->ok()) << "no Vulkan device (mesa-vulkan-drivers brings lavapipe)";
    ASSERT_TRUE(slot->validated()) << "VK_LAYER_KHRONOS_validation missing (vulkan-validationlayers)";
    std::string error;
    Device device = slot->device();
    device.buffer_device_address = buffer_device_address();
    gpu_ = Reconstructor::create(device, &error);
    ASSERT_NE(gpu_, nullptr) << error;
    vkGetPhysicalDeviceMemoryProperties(slot->device().physical_device, &memory_);
    engine_.device = slot->device().device;
    engine_.memory = &memory_;
    engine_.fill_bits = bits_of(kConstant);
    tables_ = small_tables();
    gpu_tables_ = gpu_->upload_tables(tables_, &error);
    ASSERT_NE(gpu_tables_, nullptr) << error;
    eye_ = gpu_->create_eye(kViewW, kViewH, &error);
    ASSERT_NE(eye_, nullptr) << error;
    settings_.rays_per_point = int(kRaysPerPoint);
    settings_.new_jitter_each_frame = true;
    settings_.reconstruct_on_cpu = false;
  }
  void TearDown() override {
    eye_.reset();
    gpu_tables_.reset();
    gpu_.reset();
    if (vulkan_in_use_ != nullptr && vulkan_in_use_->ok()) {
      const auto errors = vulkan_in_use_->errors();
      EXPECT_TRUE(errors.empty()) << errors.size() << " validation error(s), the first: " << errors.front();
    }
  }

  // The device trace of `view`'s planned frame `req` through the test engine, with the
  // view's content density.
  DeviceTraceFrame device_of(const foveation::FoveatedView& view, const foveation::FrameRequest& req) {
    DeviceTraceFrame device;
    device.engine = [this](const DeviceRayBatch& batch) { return test_engine(&engine_, &batch); };
    device.points = &tables_->points;
    device.view = req.view;
    device.mapping = view.hand_off().mapping;
    device.frame_index = req.frame_index;
    device.sample_seed = view.hand_off().sample_seed;
    device.rays_per_point = uint32_t(view.settings().rays_per_point);
    device.pixel_filter = view.settings().pixel_filter;
    device.density = view.settings().content_density;
    if (device.density.enabled()) {
      foveation::Executor executor(1);
      device.levels = &tables_->levels(executor);  // built once per table set
    }
    return device;
  }

  // One device-traced frame of `view` through the test engine, on `eye` (null:
  // eye_); false when the submission was refused.
  bool device_frame(foveation::FoveatedView& view, const foveation::FrameRequest& req, std::string* error,
                    Eye* eye = nullptr) {
    if (eye == nullptr) eye = eye_.get();
    foveation::Executor executor(2);
    EXPECT_TRUE(view.plan(req, executor).ok());
    const DeviceTraceFrame device = device_of(view, req);
    EyeFrame frame = EyeFrame::of(*gpu_tables_, view.hand_off(), true);
    frame.device = &device;
    frame.slot = uint32_t(req.frame_index % kFrameSlots);  // as the layer runs frames in flight
    return gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) { return eye->record(cb, frame, VK_NULL_HANDLE, executor, error); }, error);
  }

  // Device-traced frames first_index, first_index + 1, ... recorded one after the
  // other into one submission, as the layer does with frames in flight: frame i
  // into slot slots[i], the engine filling every colour word with fill_bits[i].
  bool frames_in_one_submission(foveation::FoveatedView& view, uint64_t first_index, std::vector<uint32_t> slots,
                                std::vector<uint32_t> fill_bits, std::string* error) {
    foveation::Executor executor(2);
    return gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) {
          for (std::size_t i = 0; i < slots.size(); ++i) {
            const foveation::FrameRequest req = request(glm::vec2(48, 40), first_index + i);
            if (!view.plan(req, executor).ok()) return false;
            engine_.fill_bits = fill_bits[i];
            const DeviceTraceFrame device = device_of(view, req);
            EyeFrame frame = EyeFrame::of(*gpu_tables_, view.hand_off(), true);
            frame.device = &device;
            frame.slot = slots[i];
            if (!eye_->record(cb, frame, VK_NULL_HANDLE, executor, error)) return false;
          }
          return true;
        },
        error);
  }

  // Per point of the set: visible at `mapping` (the CPU's test, foveation::VisibleRegion).
  std::vector<bool> visible_at(const foveation::GazeMapping& mapping) const {
    const foveation::PointSet& points = tables_->points;
    const foveation::VisibleRegion region(mapping, points.visible_margin_px);
    std::vector<bool> visible(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) visible[i] = region.contains(region.to_screen(points.position_px[i]));
    return visible;
  }

  // Points of slot `slot`'s resolved colours whose having a colour (a = 1) is not `expected`'s.
  std::size_t coloured_unlike(uint32_t slot, const std::vector<bool>& expected) {
    std::vector<float> rgba;
    std::string error;
    EXPECT_TRUE(eye_->read_point_colors(slot, &rgba, &error)) << error;
    if (rgba.size() < 4 * expected.size()) return expected.size();
    std::size_t unlike = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) unlike += (rgba[4 * i + 3] == 1.0f) != expected[i] ? 1 : 0;
    return unlike;
  }

  // The control words (shader_interface/device_trace.h) of the last device-traced
  // frame, copied back after it: its counts and the indirect dispatches it ran.
  std::vector<uint32_t> last_control_words() {
    const BufferRange control{engine_.last.ray_count.buffer, 0, FOVEART_DEVICE_CONTROL_WORDS * 4};
    BoundBuffer copy;
    std::string error;
    const bool ok = gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) {
          memory_barrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
          if (!engine_.readback(copy, control, cb)) return false;
          memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                         VK_ACCESS_HOST_READ_BIT);
          return true;
        },
        &error);
    EXPECT_TRUE(ok) << error;
    std::vector<uint32_t> words(FOVEART_DEVICE_CONTROL_WORDS, 0);
    if (ok) std::memcpy(words.data(), copy.mapped, words.size() * 4);
    destroy_buffer(engine_.device, &copy);
    return words;
  }

  // The same frame with the colours coming from the CPU callback.
  bool callback_frame(foveation::FoveatedView& view, const foveation::FrameRequest& req, FoveartTraceRaysFn trace,
                      void* user, std::string* error) {
    foveation::Executor executor(2);
    EXPECT_TRUE(view.render(req, trace, user, executor).ok());
    EyeFrame frame = EyeFrame::of(*gpu_tables_, view.hand_off(), true);
    return gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) { return eye_->record(cb, frame, VK_NULL_HANDLE, executor, error); }, error);
  }

  static std::unique_ptr<HeadlessVulkan> vulkan_;  // shared by the suites; made on first use
  static std::unique_ptr<HeadlessVulkan> addressed_vulkan_;  // ... with bufferDeviceAddress
  HeadlessVulkan* vulkan_in_use_ = nullptr;                 // this test's
  VkPhysicalDeviceMemoryProperties memory_{};
  std::unique_ptr<Reconstructor> gpu_;
  std::shared_ptr<const foveation::ViewTables> tables_;
  std::shared_ptr<Tables> gpu_tables_;
  std::unique_ptr<Eye> eye_;
  foveation::ViewSettings settings_;
  TestEngine engine_;
};
inline std::unique_ptr<HeadlessVulkan> DeviceTraceFixture::vulkan_;
inline std::unique_ptr<HeadlessVulkan> DeviceTraceFixture::addressed_vulkan_;

}  // namespace foveart::gpu::device_test
