// The device trace (gpu/device_trace.hpp, shaders/device_*.comp) on
// lavapipe, under VK_LAYER_KHRONOS_validation with synchronization validation:
// the rays made on the device are the CPU path's rays (same points, same
// jitter), in the point set's order and the same on every run, a frame traced on the device reconstructs as the CPU-callback frame
// of the same colours does, the engine's faults (an error, NaN or negative
// colours, a trace that records nothing) are found and counted, and per frame
// the host writes nothing and reads back only the resolve's status and the
// timestamps.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "device_trace_harness.hpp"
#include "gpu/device_stages.hpp"
#include "gpu/shader_interface/device_rays.h"

namespace foveart::gpu {
namespace {

using namespace device_test;  // NOLINT(google-build-using-namespace): the harness is this file's

// The rays the CPU path hands its callback: per point, its samples in order.
struct CpuRays {
  std::mutex mutex;
  std::map<uint32_t, std::vector<std::pair<glm::vec2, glm::vec3>>> by_point;
};

int32_t record_cpu_rays(void* user, const FoveartRayBatch* batch) {
  auto* rays = static_cast<CpuRays*>(user);
  std::lock_guard lock(rays->mutex);
  for (uint32_t i = 0; i < batch->ray_count; ++i) {
    rays->by_point[batch->point_index[i]].push_back(
        {glm::vec2(batch->sample_px[2 * i], batch->sample_px[2 * i + 1]),
         glm::vec3(batch->directions[3 * i], batch->directions[3 * i + 1], batch->directions[3 * i + 2])});
  }
  return constant_colour(nullptr, batch);
}

class DeviceTraceTest : public DeviceTraceFixture {};

// Stages 1-2 on the device give the CPU's points and rays: the same visible
// points, each with its samples in order. A pixel-grid point's jitter is
// bit-exact (integer hashing); a disc point's rounds its uniforms to float
// (1e-3 px is a thousandth of a pixel); directions follow within 1e-5.
TEST_F(DeviceTraceTest, DeviceRaysAreTheCpuRays) {
  for (glm::vec2 gaze : {glm::vec2(48, 40), glm::vec2(3, 77)}) {  // centred, and a corner (margin points left of 0)
    CpuRays cpu;
    foveation::FoveatedView cpu_view(tables_, settings_);
    std::string error;
    ASSERT_TRUE(callback_frame(cpu_view, request(gaze, 7), &record_cpu_rays, &cpu, &error)) << error;
    engine_.copy = true;
    foveation::FoveatedView device_view(tables_, settings_);
    ASSERT_TRUE(device_frame(device_view, request(gaze, 7), &error)) << error;

    const auto* control = static_cast<const uint32_t*>(engine_.control.mapped);
    const uint32_t count = control[0];
    ASSERT_EQ(count, cpu.by_point.size() * kRaysPerPoint);
    EXPECT_EQ(control[1], (count + 63) / 64);  // dispatch64
    EXPECT_EQ(control[2], 1u);
    EXPECT_EQ(control[4], count);  // trace rays: one row of count (fewer than 65536)
    EXPECT_EQ(control[5], 1u);
    EXPECT_LE(count, engine_.last.ray_capacity);
    EXPECT_EQ(engine_.last.rays_per_point, kRaysPerPoint);
    const auto* rays = static_cast<const float*>(engine_.rays.mapped);
    const auto* points = static_cast<const uint32_t*>(engine_.point_index.mapped);
    float worst_px = 0.0f, worst_dir = 0.0f;
    std::size_t grid_points = 0;
    for (uint32_t first = 0; first < count; first += kRaysPerPoint) {
      const uint32_t p = points[first];
      const auto it = cpu.by_point.find(p);
      ASSERT_NE(it, cpu.by_point.end()) << "point " << p << " traced on the device only";
      ASSERT_EQ(it->second.size(), kRaysPerPoint);
      grid_points += tables_->points.on_pixel_grid(p) ? 1 : 0;
      for (uint32_t s = 0; s < kRaysPerPoint; ++s) {
        const float* r = rays + 8 * (first + s);
        EXPECT_EQ(points[first + s], p);
        const glm::vec2 sample(r[3], r[7]);
        const glm::vec3 dir(r[4], r[5], r[6]);
        const float px = glm::length(sample - it->second[s].first);
        if (tables_->points.on_pixel_grid(p)) {
          EXPECT_EQ(px, 0.0f) << "grid point " << p << " sample " << s;
        }
        worst_px = std::max(worst_px, px);
        worst_dir = std::max(worst_dir, glm::length(dir - it->second[s].second));
        EXPECT_NEAR(r[0], -0.032f, 1e-6f);  // the eye's position
      }
    }
    EXPECT_GT(grid_points, 0u);
    EXPECT_LT(grid_points, count / kRaysPerPoint);  // disc points too
    EXPECT_LE(worst_px, 1e-3f);
    EXPECT_LE(worst_dir, 1e-5f);
    engine_.copy = false;
    for (BoundBuffer* b : {&engine_.rays, &engine_.point_index, &engine_.control, &engine_.footprints})
      destroy_buffer(engine_.device, b);
  }
}

// Each ray carries its point's footprint (XrFoveatedDeviceRayFootprintFOVEART): the angle
// at the eye of the point's disc radius, the same for all its rays, as the host computes
// it from the point's screen position; the periphery's discs wider than the pixel grid's.
TEST_F(DeviceTraceTest, EachRayCarriesItsPointsDiscRadiusAsAnAngle) {
  engine_.copy = true;
  foveation::FoveatedView view(tables_, settings_);
  const foveation::FrameRequest req = request(glm::vec2(48, 40), 3);
  std::string error;
  ASSERT_TRUE(device_frame(view, req, &error)) << error;
  const DeviceTraceFrame device = device_of(view, req);
  const foveation::EyeFrustum frustum = foveation::eye_frustum(req.view);
  const foveation::EyePose pose = foveation::eye_pose(req.view);
  const uint32_t count = static_cast<const uint32_t*>(engine_.control.mapped)[0];
  ASSERT_GT(count, 0u);
  EXPECT_EQ(engine_.last.footprints.size, VkDeviceSize{engine_.last.ray_capacity} * 4);
  const auto* points = static_cast<const uint32_t*>(engine_.point_index.mapped);
  const auto* footprint_rad = static_cast<const float*>(engine_.footprints.mapped);
  float grid_max = 0.0f, disc_max = 0.0f, worst = 0.0f;
  for (uint32_t r = 0; r < count; ++r) {
    const uint32_t p = points[r];
    const glm::vec2 screen = device.mapping.screen_from_canvas(tables_->points.position_px[p]);
    const glm::vec3 d0 = foveation::eye_ray_direction(frustum, pose, screen);
    const glm::vec3 d1 =
        foveation::eye_ray_direction(frustum, pose, screen + glm::vec2(tables_->points.radius_px[p], 0.0f));
    const float expected = 2.0f * std::asin(0.5f * glm::length(d1 - d0));
    ASSERT_GT(footprint_rad[r], 0.0f) << "ray " << r;
    worst = std::max(worst, std::abs(footprint_rad[r] - expected) / expected);
    float& side_max = tables_->points.on_pixel_grid(p) ? grid_max : disc_max;
    side_max = std::max(side_max, footprint_rad[r]);
    if (r % kRaysPerPoint != 0) {
      EXPECT_EQ(footprint_rad[r], footprint_rad[r - 1]) << "point " << p;
    }
  }
  EXPECT_LT(worst, 1e-3f) << "relative to the host's angle";
  EXPECT_GT(disc_max, grid_max) << "the periphery's discs are wider than the pixel grid's";
  engine_.copy = false;
  for (BoundBuffer* b : {&engine_.rays, &engine_.point_index, &engine_.control, &engine_.footprints})
    destroy_buffer(engine_.device, b);
}

// Without bufferDeviceAddress on the app's device, the batch's addresses are 0.
TEST_F(DeviceTraceTest, NoAddressesWithoutTheFeature) {
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  ASSERT_TRUE(device_frame(view, request(glm::vec2(48, 40), 1), &error)) << error;
  const DeviceRayBatch::Addresses& a = engine_.last.addresses;
  for (const VkDeviceAddress address : {a.ray_count, a.rays, a.point_index, a.colors, a.footprints})
    EXPECT_EQ(address, 0u);
}

// With it, every buffer of the batch has SHADER_DEVICE_ADDRESS usage and an address:
// the layer's vkGetBufferDeviceAddress of a buffer without that usage, or of memory
// allocated without DEVICE_ADDRESS, is a validation error (checked in TearDown).
class DeviceTraceAddressTest : public DeviceTraceFixture {
 protected:
  bool buffer_device_address() const override { return true; }
};

TEST_F(DeviceTraceAddressTest, TheBatchsBuffersHaveDeviceAddresses) {
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  ASSERT_TRUE(device_frame(view, request(glm::vec2(48, 40), 1), &error)) << error;
  const DeviceRayBatch& batch = engine_.last;
  const DeviceRayBatch::Addresses& a = batch.addresses;
  const VkDeviceAddress all[] = {a.ray_count, a.rays, a.point_index, a.colors, a.footprints};
  for (const VkDeviceAddress address : all) EXPECT_NE(address, 0u);
  for (std::size_t i = 0; i < std::size(all); ++i)
    for (std::size_t j = i + 1; j < std::size(all); ++j) EXPECT_NE(all[i], all[j]) << i << ", " << j;
  EXPECT_EQ(a.ray_count % 4, 0u) << "vkCmdTraceRaysIndirectKHR's address + 16 must be 4-aligned";
  EXPECT_EQ(engine_.calls, 1u);
}

// The ray order is deterministic: the visible points are compacted in the
// point set's order (device_rays.comp: per-block ray sums, a scan of the
// blocks, the writes), so two runs of the same frame give the same ray and
// point-index buffers byte for byte, each point's rays consecutive and the
// points in increasing index order, over many blocks of points and a partly
// visible one at the corner.
TEST_F(DeviceTraceTest, RaysAreInThePointSetOrderAndTheSameOnEveryRun) {
  ASSERT_GT(tables_->points.size(), 4u * FOVEART_DEVICE_RAYS_BLOCK) << "the frame spans several blocks";
  engine_.copy = true;
  for (glm::vec2 gaze : {glm::vec2(48, 40), glm::vec2(3, 77)}) {
    std::vector<uint8_t> first_rays, first_points;
    for (int run = 0; run < 3; ++run) {
      foveation::FoveatedView view(tables_, settings_);
      std::string error;
      ASSERT_TRUE(device_frame(view, request(gaze, 11), &error)) << error;
      const uint32_t count = static_cast<const uint32_t*>(engine_.control.mapped)[0];
      ASSERT_GT(count, 0u);
      const auto* rays = static_cast<const uint8_t*>(engine_.rays.mapped);
      const auto* points = static_cast<const uint32_t*>(engine_.point_index.mapped);
      std::vector<uint8_t> ray_bytes(rays, rays + std::size_t(count) * sizeof(shader::DeviceRay));
      std::vector<uint8_t> point_bytes(reinterpret_cast<const uint8_t*>(points),
                                       reinterpret_cast<const uint8_t*>(points + count));
      for (uint32_t r = 0; r < count; ++r) {
        if (r % kRaysPerPoint != 0) {
          ASSERT_EQ(points[r], points[r - 1]) << "ray " << r << ": a point's rays are consecutive";
        } else if (r > 0) {
          ASSERT_GT(points[r], points[r - 1]) << "ray " << r << ": points in the set's order";
        }
      }
      if (run == 0) {
        first_rays = std::move(ray_bytes);
        first_points = std::move(point_bytes);
        continue;
      }
      EXPECT_EQ(ray_bytes, first_rays) << "run " << run << " gave other rays";
      EXPECT_EQ(point_bytes, first_points) << "run " << run << " gave another point order";
    }
  }
  engine_.copy = false;
  for (BoundBuffer* b : {&engine_.rays, &engine_.point_index, &engine_.control}) destroy_buffer(engine_.device, b);
}

// A frame of more blocks than one pass of the scan of the block sums takes (4 per
// invocation of one workgroup, scan.glsl), as every FOVE-sized frame is: the scan
// carries each pass's total into the next, so the rays are still the CPU path's,
// each point's consecutive and the points in the set's order. A carry lost
// between passes would place a later pass's rays over earlier ones.
TEST_F(DeviceTraceTest, RaysAreTheCpuRaysWhenTheScanOfBlocksTakesSeveralPasses) {
  std::string error;
  tables_ = wide_tables();
  constexpr std::size_t kPassPoints = 4u * FOVEART_DEVICE_RAYS_BLOCK * FOVEART_DEVICE_RAYS_BLOCK;  // one pass's blocks
  ASSERT_GT(tables_->points.size(), 2 * kPassPoints) << "three passes or more";
  gpu_tables_ = gpu_->upload_tables(tables_, &error);
  ASSERT_NE(gpu_tables_, nullptr) << error;
  eye_ = gpu_->create_eye(kWideViewW, kWideViewH, &error);
  ASSERT_NE(eye_, nullptr) << error;
  const foveation::FrameRequest req = request(glm::vec2(70, 90), 5, glm::uvec2(kWideViewW, kWideViewH));
  CpuRays cpu;
  foveation::FoveatedView cpu_view(tables_, settings_);
  ASSERT_TRUE(callback_frame(cpu_view, req, &record_cpu_rays, &cpu, &error)) << error;
  engine_.copy = true;
  foveation::FoveatedView device_view(tables_, settings_);
  ASSERT_TRUE(device_frame(device_view, req, &error)) << error;
  const uint32_t count = static_cast<const uint32_t*>(engine_.control.mapped)[0];
  ASSERT_EQ(count, cpu.by_point.size() * kRaysPerPoint);
  const auto* rays = static_cast<const float*>(engine_.rays.mapped);
  const auto* points = static_cast<const uint32_t*>(engine_.point_index.mapped);
  float worst_px = 0.0f;
  for (uint32_t r = 0; r < count; ++r) {
    const uint32_t s = r % kRaysPerPoint;
    if (s != 0) {
      ASSERT_EQ(points[r], points[r - 1]) << "ray " << r << ": a point's rays are consecutive";
    } else if (r > 0) {
      ASSERT_GT(points[r], points[r - 1]) << "ray " << r << ": points in the set's order";
    }
    const auto it = cpu.by_point.find(points[r]);
    ASSERT_NE(it, cpu.by_point.end()) << "point " << points[r] << " traced on the device only";
    worst_px = std::max(worst_px, glm::length(glm::vec2(rays[8 * r + 3], rays[8 * r + 7]) - it->second[s].first));
  }
  EXPECT_LE(worst_px, 1e-3f);
  ASSERT_GT(count, 0u);
  EXPECT_LT(points[0], kPassPoints) << "traced points in the first pass's blocks";
  EXPECT_GE(points[count - 1], 2 * kPassPoints) << "and in the third's";
  engine_.copy = false;
  for (BoundBuffer* b : {&engine_.rays, &engine_.point_index, &engine_.control, &engine_.footprints})
    destroy_buffer(engine_.device, b);
}

// Colours resolved on the device reconstruct as the callback's: a device
// frame and a CPU-callback frame whose engines both answer each ray with its
// direction (and its screen y as depth) give the same image, within one 8-bit
// step (the directions agree within 1e-5), with an image history over a gaze jump.
TEST_F(DeviceTraceTest, DeviceFrameReconstructsAsTheCallbackFrame) {
  settings_.temporal = foveation::TemporalMode::image;
  engine_.answer = TestEngine::Answer::direction;
  foveation::FoveatedView device_view(tables_, settings_), callback_view(tables_, settings_);
  std::vector<uint8_t> first;
  for (uint64_t i = 0; i < 4; ++i) {
    const foveation::FrameRequest req = request(i < 2 ? glm::vec2(40, 30) : glm::vec2(70, 60), i);
    std::string error;
    ASSERT_TRUE(callback_frame(callback_view, req, &direction_colour, nullptr, &error)) << error;
    std::vector<uint8_t> expected, actual;
    ASSERT_TRUE(eye_->read_rgba8(&expected, &error)) << error;
    ASSERT_TRUE(device_frame(device_view, req, &error)) << error;
    EXPECT_EQ(eye_->device_trace_status().invalid_components, 0u);
    ASSERT_TRUE(eye_->read_rgba8(&actual, &error)) << error;
    ASSERT_EQ(actual.size(), expected.size());
    int worst = 0;
    for (std::size_t b = 0; b < actual.size(); ++b) worst = std::max(worst, std::abs(int(actual[b]) - int(expected[b])));
    EXPECT_LE(worst, 1) << "frame " << i;
    EXPECT_EQ(device_view.hand_off().temporal.reset, callback_view.hand_off().temporal.reset) << "frame " << i;
    if (i == 0) first = actual;
  }
  EXPECT_EQ(engine_.calls, 4u);
  // The colours vary over the image: the comparison is not of a flat field.
  std::size_t distinct_red = 0;
  std::vector<bool> seen(256, false);
  for (std::size_t b = 0; b < first.size(); b += 4) distinct_red += seen[first[b]] ? 0 : (seen[first[b]] = true, 1);
  EXPECT_GT(distinct_red, 20u);
}

// The device's stage set (make_device_stages), run by FoveatedView into a
// DeviceFrame, records the frame gpu::Eye records from a planned hand-off,
// bit for bit; an engine error fails the frame as the engine's, not the device's.
TEST_F(DeviceTraceTest, DeviceStageSetRecordsTheEyesFrame) {
  settings_.temporal = foveation::TemporalMode::image;
  engine_.answer = TestEngine::Answer::direction;
  foveation::FoveatedView planned(tables_, settings_);
  foveation::FoveatedView staged(
      tables_, settings_,
      make_device_stages(tables_, settings_,
                         [this](const DeviceRayBatch& batch) { return test_engine(&engine_, &batch); }));
  std::string error;
  const auto staged_eye = gpu_->create_eye(kViewW, kViewH, &error);
  ASSERT_NE(staged_eye, nullptr) << error;
  foveation::Executor executor(2);
  const auto run_staged = [&](const foveation::FrameRequest& req) {
    DeviceFrame frame;
    frame.eye = staged_eye.get();
    frame.tables = gpu_tables_.get();
    frame.slot = uint32_t(req.frame_index % kFrameSlots);
    foveation::FrameResult result;
    (void)gpu_->submit_and_wait(
        [&](VkCommandBuffer cb) {
          frame.cb = cb;
          result = staged.render(req, nullptr, nullptr, frame, executor);
          return result.ok();
        },
        &error);
    return result;
  };
  for (uint64_t i = 0; i < 4; ++i) {
    const foveation::FrameRequest req = request(i < 2 ? glm::vec2(40, 30) : glm::vec2(70, 60), i);
    ASSERT_TRUE(device_frame(planned, req, &error)) << error;
    const foveation::FrameResult result = run_staged(req);
    ASSERT_TRUE(result.ok()) << result.message << error;
    std::vector<uint8_t> expected, actual;
    ASSERT_TRUE(eye_->read_rgba8(&expected, &error)) << error;
    ASSERT_TRUE(staged_eye->read_rgba8(&actual, &error)) << error;
    EXPECT_EQ(actual, expected) << "frame " << i;
    EXPECT_EQ(staged.hand_off().temporal.reset, planned.hand_off().temporal.reset) << "frame " << i;
    EXPECT_EQ(staged_eye->device_trace_status().visible_points, eye_->device_trace_status().visible_points);
  }
  engine_.answer = TestEngine::Answer::error;
  const foveation::FrameResult failed = run_staged(request(glm::vec2(48, 40), 4));
  EXPECT_EQ(failed.failure, foveation::FrameFailure::callback_failed);
  EXPECT_EQ(failed.failed_batches, 1u);
  EXPECT_NE(failed.message.find("device trace"), std::string::npos) << failed.message;
}

// Per frame the device path writes nothing to host memory and reads back the
// resolve's status and the stage timestamps only; the callback path uploads
// every traced point's colour.
TEST_F(DeviceTraceTest, OnlyConstantsCrossToTheHost) {
  foveation::FoveatedView device_view(tables_, settings_), callback_view(tables_, settings_);
  std::string error;
  for (uint64_t i = 0; i < 2 * kFrameSlots; ++i) {
    ASSERT_TRUE(device_frame(device_view, request(glm::vec2(48, 40), i), &error)) << error;
    StageTimes times;
    EXPECT_TRUE(eye_->stage_times(&times));
    // Content density is off: its passes' spans read 0, not the cost of the stamps around nothing.
    EXPECT_EQ(times.density_fill_ms, 0.0f);
    EXPECT_EQ(times.density_contrast_ms, 0.0f);
    EXPECT_GT(times.trace_ms, 0.0f);
    const DeviceTraceStatus status = eye_->device_trace_status();
    EXPECT_GT(status.visible_points, 0u);
    // The first frame of a table set in each frame slot copies its points up
    // once (16 bytes each): each slot has its own device trace.
    EXPECT_EQ(eye_->host_bytes_written(), i < kFrameSlots ? tables_->points.size() * 16 : 0u) << "frame " << i;
    EXPECT_EQ(eye_->host_bytes_read(), FOVEART_DEVICE_STATUS_WORDS * 4 + StageTimes::kTimestamps * sizeof(uint64_t));
  }
  ASSERT_TRUE(callback_frame(callback_view, request(glm::vec2(48, 40), 2 * kFrameSlots), &constant_colour, nullptr, &error)) << error;
  EXPECT_GE(eye_->host_bytes_written(), 20u * 1000u);  // (index, rgb, depth) per traced point
}

// The engine's faults: an error (nothing is submitted), NaN or negative
// colours, and a trace that records nothing (its rays stay NaN) are found on
// the device and counted per colour component.
TEST_F(DeviceTraceTest, EngineFaultsAreFoundAndCounted) {
  foveation::FoveatedView view(tables_, settings_);
  std::string error;
  engine_.answer = TestEngine::Answer::error;
  EXPECT_FALSE(device_frame(view, request(glm::vec2(48, 40), 1), &error));
  EXPECT_EQ(engine_.calls, 1u);
  EXPECT_NE(error.find("device trace"), std::string::npos) << error;

  engine_.answer = TestEngine::Answer::fill;
  ASSERT_TRUE(device_frame(view, request(glm::vec2(48, 40), 2), &error)) << error;
  const uint32_t visible = eye_->device_trace_status().visible_points;
  ASSERT_GT(visible, 0u);
  EXPECT_EQ(eye_->device_trace_status().invalid_components, 0u);

  const uint64_t components = uint64_t(visible) * kRaysPerPoint * 3;
  for (uint32_t bits : {0x7FC00000u /* NaN */, 0x7F800000u /* +inf */, bits_of(-0.5f)}) {
    engine_.fill_bits = bits;
    ASSERT_TRUE(device_frame(view, request(glm::vec2(48, 40), 3), &error)) << error;
    EXPECT_EQ(eye_->device_trace_status().invalid_components, components) << std::hex << bits;
  }
  engine_.answer = TestEngine::Answer::nothing;
  ASSERT_TRUE(device_frame(view, request(glm::vec2(48, 40), 4), &error)) << error;
  EXPECT_EQ(eye_->device_trace_status().invalid_components, components);
}

// Two frames in flight, each in its own slot of the eye, recorded into one
// submission: each slot keeps its own status, and a frame whose colours are
// NaN (found by the resolve) leaves the shown image as the last good frame
// wrote it, decided on the device; the good frames' image is grey, the NaN
// frame's would be black (NaN encodes as 0).
TEST_F(DeviceTraceTest, EachSlotKeepsItsStatusAndAFaultKeepsTheShownImage) {
  foveation::FoveatedView view(tables_, settings_);
  engine_.answer = TestEngine::Answer::fill;
  const uint32_t grey = bits_of(0.25f), nan = 0x7FC00000u;
  std::string error;
  ASSERT_TRUE(frames_in_one_submission(view, 1, {0}, {grey}, &error)) << error;
  std::vector<uint8_t> good;
  ASSERT_TRUE(eye_->read_rgba8(&good, &error)) << error;
  ASSERT_GT(*std::max_element(good.begin(), good.end()), 0) << "the good frame is not black";
  for (const bool fault_first : {true, false}) {
    SCOPED_TRACE(fault_first ? "fault, then a good frame" : "a good frame, then a fault");
    const std::vector<uint32_t> fills = fault_first ? std::vector{nan, grey} : std::vector{grey, nan};
    ASSERT_TRUE(frames_in_one_submission(view, 2, {1, 0}, fills, &error)) << error;
    EXPECT_EQ(eye_->device_trace_status(1).invalid_components > 0, fault_first);
    EXPECT_EQ(eye_->device_trace_status(0).invalid_components > 0, !fault_first);
    EXPECT_GT(eye_->device_trace_status(0).visible_points, 0u);
    EXPECT_EQ(eye_->device_trace_status(0).visible_points, eye_->device_trace_status(1).visible_points);
    std::vector<uint8_t> shown;
    ASSERT_TRUE(eye_->read_rgba8(&shown, &error)) << error;
    EXPECT_TRUE(shown == good) << "the shown image is not the last good frame's";
  }
}

// The resolve runs a thread per traced point, not one per point of the set: the
// rays pass's SCAN sizes its indirect dispatch on the device. After a frame its
// groups are those of the visible points (the CPU's test; without content density
// all are traced), fewer than the whole set's (the set extends beyond the screen so
// the gaze can move), there is no fill, and the compacted entries it ran over gave
// every visible point, and no other, its colour.
TEST_F(DeviceTraceTest, ResolveRunsAGroupPerTracedPointsOnly) {
  const uint32_t group = FOVEART_DEVICE_RESOLVE_GROUP;
  const auto groups = [group](std::size_t n) { return uint32_t((n + group - 1) / group); };
  for (glm::vec2 gaze : {glm::vec2(48, 40), glm::vec2(3, 77)}) {
    foveation::FoveatedView view(tables_, settings_);
    const foveation::FrameRequest req = request(gaze, 5);
    std::string error;
    ASSERT_TRUE(device_frame(view, req, &error)) << error;
    const std::vector<bool> visible = visible_at(view.hand_off().mapping);
    const auto traced = uint32_t(std::count(visible.begin(), visible.end(), true));
    ASSERT_GT(traced, 0u);
    const std::vector<uint32_t> control = last_control_words();
    EXPECT_EQ(control[FOVEART_DEVICE_TRACED_POINTS], traced);
    EXPECT_EQ(control[FOVEART_DEVICE_VISIBLE_POINTS], traced);
    EXPECT_EQ(control[FOVEART_DEVICE_RESOLVE_DISPATCH], groups(traced));
    EXPECT_EQ(control[FOVEART_DEVICE_RESOLVE_DISPATCH + 1], 1u);
    EXPECT_EQ(control[FOVEART_DEVICE_RESOLVE_DISPATCH + 2], 1u);
    EXPECT_LT(control[FOVEART_DEVICE_RESOLVE_DISPATCH], groups(tables_->points.size()));
    EXPECT_EQ(control[FOVEART_DEVICE_FILL_DISPATCH], 0u);
    EXPECT_EQ(eye_->device_trace_status().traced_points, traced);
    EXPECT_EQ(coloured_unlike(uint32_t(req.frame_index % kFrameSlots), visible), 0u) << "gaze " << gaze.x;
    std::cout << "[ work count ] gaze (" << gaze.x << ", " << gaze.y << "): the resolve runs "
              << control[FOVEART_DEVICE_RESOLVE_DISPATCH] << " groups for " << traced << " traced points of "
              << tables_->points.size() << " (the whole set: " << groups(tables_->points.size()) << ")\n";
  }
}

}  // namespace
}  // namespace foveart::gpu
