// The layer's side of a foveated frame: OpenXR views in, the one foveated
// frame of foveation/ (foveation::FoveatedView) per eye, running the stage set
// chosen for the eye once (the CPU's, or the device's: gpu/device_stages.hpp),
// RGBA8 into the layer's swapchain, the rewritten subImage out. Gaze comes from the
// renderer's gaze source; tables are built in the background per view size (renderer_tables.cpp).
// On the GPU path both eyes of a frame are recorded into one command buffer of
// the frame's slot and submitted once; their status and timestamps are read
// when the slot comes round again (frame_submission.hpp, docs/gpu.md).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "foveation/cache_dir.hpp"
#include "foveation/eye_view_check.hpp"
#include "foveation/rgba8.hpp"
#include "layer/sampling_defaults.hpp"
#include "log.hpp"
#include "next_chain.hpp"
#include "renderer_frames.hpp"
#include "xr_glm.hpp"

namespace foveart::layer {
namespace {

// The config's cache_dir, else foveation's default; nullopt (no cache) with *why
// when the default directory is refused.
std::optional<std::filesystem::path> cache_dir(const RendererSettings& settings, std::string* why) {
  if (!settings.cache_dir.empty()) return std::filesystem::path(settings.cache_dir);
  return foveation::default_cache_dir(why);
}

XrFoveatedFallbackFlagsFOVEART fallback_flag(foveation::FrameFailure failure) {
  switch (failure) {
    case foveation::FrameFailure::callback_failed: return XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART;
    case foveation::FrameFailure::invalid_colour: return XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART;
    case foveation::FrameFailure::resources_failed: return XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
    case foveation::FrameFailure::none: break;
  }
  return 0;
}

}  // namespace


FoveatedRenderer::Frames::Frames(std::shared_ptr<SessionState> session_in, const RendererSettings& settings_in,
                                 InputCounters& input_in, ReconstructionStats& reconstruction_in,
                                 DensityStats& density_in)
    : session(std::move(session_in)),
      settings(settings_in),
      input(input_in),
      reconstruction(reconstruction_in),
      density(density_in),
      executor(settings_in.threads) {
  std::string warning;
  gaze = create_gaze_source(settings, *session, &warning);
  if (!warning.empty()) log(LogLevel::Warn, "foveated renderer: ", warning);
  std::string why;
  cache = cache_dir(settings, &why);
  if (!cache) {
    ++input.cache_failures;
    log(LogLevel::Warn, "foveated renderer: ", why, "; tables are built without a cache (counted in the stats)");
  }
  choose_reconstruction();
  builder = std::thread([this] { build_tables(); });
}

FoveatedRenderer::Frames::~Frames() {
  {
    std::lock_guard lock(build_mutex);
    stop_building = true;
  }
  cancel_build = true;  // the build in progress stops at its next progress report
  build_wake.notify_all();
  builder.join();
}

uint32_t FoveatedRenderer::Frames::render(XrTime display_time, const XrCompositionLayerProjection& layer,
                                          XrCompositionLayerProjectionView* views, const std::vector<bool>& rect_valid,
                                          const XrFoveatedDisplayTransformFOVEART* chained_display,
                                          XrFoveatedRendererStatsFOVEART* stats) {
  const std::optional<TakenRayBatch> taken = batches.take();  // the app-recorded trace's, when acquired
  if (!frame_started) ++frame_index;
  frame_started = false;
  std::string display_error;
  display = resolve_display(chained_display, settings.display, &display_error);
  if (!display_error.empty() && display_once.first())
    log(LogLevel::Warn, "xrEndFrame: ", display_error, "; the config's value is used (logged once)");
  const FrameGaze frame_gaze = gaze_at(display_time, layer.space, views, layer.viewCount, stats);
  if (taken) took_batch(*taken, stats);

  const uint32_t slot = uint32_t(frame_index % gpu::kFrameSlots);
  collect(slot, stats);
  uint32_t rewritten = 0;
  const uint32_t eye_count = std::min<uint32_t>(layer.viewCount, 2);
  XrSwapchainSubImage app_sub_images[2] = {};
  for (uint32_t e = 0; e < eye_count; ++e) app_sub_images[e] = views[e].subImage;
  for (uint32_t e = 0; e < eye_count; ++e) {
    if (e >= rect_valid.size() || !rect_valid[e]) {
      // The runtime judges the app's rect; the layer neither traces nor rewrites it.
      ++input.invalid_image_rect_views;
      stats->fallbackFlags |= XR_FOVEATED_FALLBACK_INVALID_IMAGE_RECT_BIT_FOVEART;
      if (rect_once.first()) {
        const auto& r = views[e].subImage.imageRect;
        log(LogLevel::Warn, "foveated renderer: eye ", e, ": imageRect (", r.offset.x, ",", r.offset.y, ") ",
            r.extent.width, "x", r.extent.height, " lies outside its swapchain image; forwarded as the app sent it, "
            "not ray traced (logged once, counted in the stats)");
      }
      ++stats->framesFallback;
      continue;
    }
    const auto& rect = views[e].subImage.imageRect;  // positive: checked above
    const FoveartEyeView submitted =
        eye_view_of(e, views[e].pose, views[e].fov, uint32_t(rect.extent.width), uint32_t(rect.extent.height));
    if (view_traceable(e, submitted, "xrEndFrame", stats) &&
        (taken ? render_app_eye(e, *taken, views[e], stats) : render_eye(e, frame_gaze, submitted, views[e], stats)))
      ++rewritten;
    else
      ++stats->framesFallback;
  }
  if (taken && taken->released && submission != nullptr && submission->begun(slot)) {
    std::string error;  // the current semaphore: a released batch never changes it
    submission->wait_before(slot, submission->timeline(batches.semaphore_generation(), &error), taken->traced_value);
  }
  rewritten -= finish_gpu_frame(slot, views, app_sub_images, stats);
  stats->framesFallback += layer.viewCount - eye_count;  // views beyond two stay the app's
  if (rewritten > 0) ++stats->framesTraced;
  return rewritten;
}

FrameGaze FoveatedRenderer::Frames::gaze_at(XrTime display_time, XrSpace space,
                                            const XrCompositionLayerProjectionView* views, uint32_t view_count,
                                            XrFoveatedRendererStatsFOVEART* stats) {
  const int64_t now_ns = steady_now_ns();
  GazeQuery query;
  query.now_ns = now_ns;
  query.display_time = display_time;
  query.runtime_clock_is_steady = std::llabs(display_time - now_ns) < 1'000'000'000;
  query.space = space;
  query.views = views;
  query.view_count = view_count;
  const FrameGaze frame_gaze = gaze->at(query);
  stats->gazeSource = frame_gaze.valid ? frame_gaze.source : XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
  stats->gazeAgeMs = frame_gaze.valid ? frame_gaze.age_ms : 0.0f;
  stats->fallbackFlags = frame_gaze.valid ? 0 : XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART;
  if (!frame_gaze.valid) ++stats->gazeLostFrames;
  reconstruction.gaze_saccade_last_frame = frame_gaze.valid && frame_gaze.saccade;
  reconstruction.gaze_blink_last_frame = frame_gaze.valid && frame_gaze.blink;
  return frame_gaze;
}

void FoveatedRenderer::Frames::choose_reconstruction() {
  if (settings.reconstruction == "cpu") {
    log(LogLevel::Info, "foveated renderer: reconstruction on the CPU (config \"reconstruction\": \"cpu\")");
    return;
  }
  VkPhysicalDeviceProperties device{};
  vkGetPhysicalDeviceProperties(session->vk_physical_device, &device);
  if (settings.reconstruction == "auto" && device.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU &&
      settings.trace_rays_device == nullptr && !settings.app_trace) {
    // A CPU Vulkan device (lavapipe) runs the shaders on the cores the CPU path
    // uses, 3-20x slower than its SIMD gather (docs/gpu.md): auto keeps the CPU.
    log(LogLevel::Info, "foveated renderer: reconstruction on the CPU: ", device.deviceName,
        " is a CPU device (config \"reconstruction\": \"gpu\" uses it anyway; so does a device or app-recorded trace)");
    return;
  }
  std::string why;
  reconstructor = gpu::Reconstructor::create(
      gpu::Device{session->vk_physical_device, session->vk_device, session->vk_queue_family_index,
                  session->vk_queue_index, session->buffer_device_address,
                  settings.app_queue_families,  // the app-recorded trace's families
                  session->vk_instance_api_version},
      &why);
  const auto& properties = device;
  if (reconstructor != nullptr) submission = FrameSubmission::create(*session, &why);
  if (submission == nullptr) reconstructor = nullptr;  // no command buffers for its frames
  if (reconstructor != nullptr) {
    log(LogLevel::Info, "foveated renderer: reconstruction on the GPU (", properties.deviceName, ", config \"",
        settings.reconstruction, "\")");
  } else if (settings.reconstruction == "gpu") {
    log(LogLevel::Error, "foveated renderer: config \"reconstruction\": \"gpu\", but ", properties.deviceName,
        " cannot run the shaders: ", why, "; reconstructing on the CPU");
  } else {
    log(LogLevel::Info, "foveated renderer: reconstruction on the CPU: ", properties.deviceName,
        " cannot run the shaders: ", why);
  }
}

std::shared_ptr<gpu::Tables> FoveatedRenderer::Frames::gpu_tables_for(
    const std::shared_ptr<const foveation::ViewTables>& view_tables, std::string* error) {
  // Sets no eye holds any more go first (a view size that is gone).
  std::erase_if(gpu_tables, [](const std::shared_ptr<gpu::Tables>& t) { return t.use_count() == 1; });
  for (const auto& t : gpu_tables)
    if (&t->view_tables() == view_tables.get()) return t;
  auto uploaded = reconstructor->upload_tables(view_tables, error);
  if (uploaded != nullptr) {
    gpu_tables.push_back(uploaded);
    log(LogLevel::Info, "foveated renderer: ", uploaded->bytes() >> 20, " MiB of tables on the GPU in ",
        uploaded->layout().chunks.size(), " buffer(s)");
  }
  return uploaded;
}

bool FoveatedRenderer::Frames::ensure_gpu_eye(uint32_t e,
                                              const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                              std::string* error) {
  Eye& eye = eyes[e];
  const uint32_t w = eye.swapchain->width_px(), h = eye.swapchain->height_px();
  if (eye.gpu_tables == nullptr || &eye.gpu_tables->view_tables() != view_tables.get()) {
    eye.gpu_tables = nullptr;
    eye.gpu_tables = gpu_tables_for(view_tables, error);
    if (eye.gpu_tables == nullptr) return false;
  }
  if (eye.gpu_eye == nullptr || eye.gpu_eye->width_px() != w || eye.gpu_eye->height_px() != h) {
    eye.gpu_eye = nullptr;  // a frame in flight keeps the old one (in_flight)
    eye.gpu_eye = reconstructor->create_eye(w, h, error);
    eye.shown_good = false;
    if (eye.gpu_eye == nullptr) return false;
  }
  return true;
}

VkCommandBuffer FoveatedRenderer::Frames::begin_on_gpu(uint32_t e,
                                                       const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                                       bool device_trace, gpu::DeviceFrame& frame, std::string* error) {
  Eye& eye = eyes[e];
  if (!ensure_gpu_eye(e, view_tables, error)) return VK_NULL_HANDLE;
  const VkCommandBuffer cb = submission->begin(frame.slot, error);
  if (cb == VK_NULL_HANDLE || !eye.swapchain->acquire(&frame.image, error)) return VK_NULL_HANDLE;
  eye.image_acquired = true;
  frame.eye = eye.gpu_eye.get();
  frame.tables = eye.gpu_tables.get();
  // Recorded in full once the eye's present marks it so (present_gpu).
  in_flight[frame.slot][e] = InFlightEye{eye.gpu_eye, eye.gpu_tables, eye.swapchain, false, device_trace,
                                         !device_trace || eye.shown_good};
  return cb;
}

bool FoveatedRenderer::Frames::device_trace_ok(uint32_t e, const gpu::DeviceTraceStatus& status,
                                               XrFoveatedRendererStatsFOVEART* stats) {
  if (status.invalid_components == 0) return true;
  stats->invalidColours += status.invalid_components;
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART;
  if (colour_once.first()) {
    log(LogLevel::Error, "foveated renderer: eye ", e, ": the device trace wrote ", status.invalid_components,
        " NaN/Inf/negative colour components (or left rays unwritten); that frame kept the view's last good image "
        "(the app's own before the first) (logged once, counted in stats)");
  }
  if (eyes[e].view != nullptr) eyes[e].view->forget_history();
  return false;
}

void FoveatedRenderer::Frames::collect(uint32_t slot, XrFoveatedRendererStatsFOVEART* stats,
                                       std::array<bool, 2>* faulted) {
  if (submission == nullptr) return;
  std::string error;
  if (!submission->wait(slot, &error) && submit_once.first())
    log(LogLevel::Error, "foveated renderer: ", error, " (logged once)");
  for (uint32_t e = 0; e < 2; ++e) {
    std::optional<InFlightEye> flight = std::move(in_flight[slot][e]);
    in_flight[slot][e].reset();
    if (!flight || !flight->recorded) continue;
    Eye& eye = eyes[e];
    const bool same_eye = flight->gpu_eye == eye.gpu_eye;
    gpu::StageTimes times;
    if (flight->gpu_eye->stage_times(slot, &times)) eye.times = times;
    bool good = true;
    if (flight->device_trace) {
      eye.status = flight->gpu_eye->device_trace_status(slot);
      good = device_trace_ok(e, *eye.status, stats);
    }
    if (good && same_eye) eye.shown_good = true;
    if (!good && flight->shown) ++stats->framesFallback;  // shown as its last good image, counted now
    if (!good && !flight->shown && faulted != nullptr) (*faulted)[e] = true;
    apply_collected(e, stats);
  }
}

void FoveatedRenderer::Frames::apply_collected(uint32_t e, XrFoveatedRendererStatsFOVEART* stats) {
  const Eye& eye = eyes[e];
  if (eye.status) {
    stats->pointsPerEye[e] = eye.status->traced_points;  // as the CPU's: visible points traced
    stats->raysPerEye[e] = static_cast<uint32_t>(std::min<uint64_t>(eye.status->rays, UINT32_MAX));
    density.points_thinned[e] = eye.status->thinned_points;
  }
  if (!eye.times) return;
  const gpu::StageTimes& times = *eye.times;
  density.gpu_fill_ms[e] = times.density_fill_ms;  // 0 unless a device trace thinned
  density.gpu_contrast_ms[e] = times.density_contrast_ms;
  reconstruction.gpu_scatter_ms[e] = times.scatter_ms;
  reconstruction.gpu_gather_ms[e] = times.gather_ms;
  reconstruction.gpu_temporal_ms[e] = times.temporal_ms;
  reconstruction.gpu_encode_ms[e] = times.encode_ms;
  if (eye.status) stats->traceMs[e] = times.trace_ms;  // the trace ran on the device: its own slot
  stats->reconstructMs[e] = times.scatter_ms + times.gather_ms;
  stats->temporalMs[e] = times.temporal_ms;
}

uint32_t FoveatedRenderer::Frames::finish_gpu_frame(uint32_t slot, XrCompositionLayerProjectionView* views,
                                                    const XrSwapchainSubImage* app_sub_images,
                                                    XrFoveatedRendererStatsFOVEART* stats) {
  if (submission == nullptr || !submission->begun(slot)) return 0;
  std::string error;
  const bool submitted = submission->submit(slot, &error);
  for (Eye& eye : eyes) {
    std::string release_error;
    if (eye.image_acquired && !eye.swapchain->release(&release_error) && submit_once.first())
      log(LogLevel::Error, "foveated renderer: ", release_error, " (logged once)");
    eye.image_acquired = false;
  }
  std::array<bool, 2> back{};  // the views that show the app's image after all
  if (!submitted) {
    if (submit_once.first()) log(LogLevel::Error, "foveated renderer: ", error, "; these views show the app's image");
    for (uint32_t e = 0; e < 2; ++e) back[e] = in_flight[slot][e] && in_flight[slot][e]->recorded;
    in_flight[slot] = {};
  }
  bool warm_up = false;  // a device-traced eye without a good shown image: waited for now
  for (const auto& flight : in_flight[slot]) warm_up = warm_up || (flight && flight->recorded && !flight->shown);
  if (warm_up) {
    std::array<bool, 2> faulted{};
    collect(slot, stats, &faulted);
    for (uint32_t e = 0; e < 2; ++e) back[e] = back[e] || faulted[e];
  }
  uint32_t fell_back = 0;
  for (uint32_t e = 0; e < 2; ++e) {
    if (!back[e]) continue;
    views[e].subImage = app_sub_images[e];
    ++stats->framesFallback;
    ++fell_back;
  }
  return fell_back;
}

bool FoveatedRenderer::Frames::ensure_swapchain(uint32_t e, uint32_t w, uint32_t h,
                                                XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  if (eye.swapchain != nullptr && eye.swapchain->width_px() == w && eye.swapchain->height_px() == h) return true;
  std::string error;
  eye.swapchain = EyeSwapchain::create(*session, w, h, &error);
  if (eye.swapchain != nullptr) return true;
  log(LogLevel::Error, "foveated renderer: eye ", e, ": cannot create the layer's swapchain: ", error,
      "; this eye shows the app's image from now on");
  eye.failed = true;
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
  return false;
}

bool FoveatedRenderer::Frames::choose_path(uint32_t e) {
  Eye& eye = eyes[e];
  EyePath path;
  path.reconstruct_on_gpu = reconstructor != nullptr && !eye.gpu_failed;
  // The engine's device trace where the GPU reconstructs; its CPU callback elsewhere.
  const bool device_traced = settings.trace_rays_device != nullptr || settings.app_trace;
  path.device_trace = path.reconstruct_on_gpu && device_traced;
  if (!path.device_trace && settings.trace_rays == nullptr) return false;  // a device trace alone, and no GPU path
  if (path.reconstruct_on_gpu) {
    choose_gpu_path(path);
  } else {
    choose_cpu_path(path);
  }
  eye.path = std::move(path);
  return true;
}

void FoveatedRenderer::Frames::choose_gpu_path(EyePath& path) {
  const bool device_trace = path.device_trace;
  path.stages = [this, device_trace](const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                     const foveation::ViewSettings& view_settings) {
    gpu::DeviceTraceEngine engine;  // empty: the engine's callback traces, its colours uploaded
    if (device_trace) {
      engine = xr_device_trace_engine(settings.trace_rays_device, settings.device_user_data, &device_engine_result);
    }
    return gpu::make_device_stages(view_tables, view_settings, std::move(engine));
  };
  path.resources = [this, device_trace](uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                        XrFoveatedRendererStatsFOVEART*) {
    return gpu_resources(e, view_tables, device_trace);
  };
  path.resources_failed = [this](uint32_t e, const std::string& error, XrFoveatedRendererStatsFOVEART* stats) {
    fall_back_to_cpu(e, error, stats);
  };
  path.present = [this](uint32_t e, XrFoveatedRendererStatsFOVEART* stats) { return present_gpu(e, stats); };
}

void FoveatedRenderer::Frames::choose_cpu_path(EyePath& path) {
  path.stages = [](const std::shared_ptr<const foveation::ViewTables>& view_tables,
                   const foveation::ViewSettings& view_settings) {
    return foveation::make_cpu_stages(view_tables, view_settings);
  };
  path.resources = [this](uint32_t e, const std::shared_ptr<const foveation::ViewTables>&,
                          XrFoveatedRendererStatsFOVEART* stats) { return cpu_resources(e, stats); };
  path.resources_failed = [this](uint32_t e, const std::string& error, XrFoveatedRendererStatsFOVEART* stats) {
    upload_failed(e, error, stats);
  };
  path.present = [this](uint32_t e, XrFoveatedRendererStatsFOVEART* stats) { return present_cpu(e, stats); };
}

void FoveatedRenderer::Frames::ensure_view(uint32_t e,
                                           const std::shared_ptr<const foveation::ViewTables>& view_tables) {
  Eye& eye = eyes[e];
  const EyePath& path = *eye.path;
  if (eye.view != nullptr && &eye.view->tables() == view_tables.get() &&
      eye.view->settings().reconstruct_on_cpu != path.reconstruct_on_gpu) {
    return;
  }
  eye.temporal = temporal_for_path(settings, path.reconstruct_on_gpu);  // a device trace's rays stay on the GPU
  if (eye.temporal == foveation::TemporalMode::rays && !path.reconstruct_on_gpu && cpu_render_cache_once.first())
    log(LogLevel::Warn,
        "temporal \"rays\" with reconstruction on the CPU: the render cache filters every ray it keeps ",
        "into the pixels each frame, so its cost grows with them, up to 32 frames' rays, to many times the image ",
        "history's; it is the GPU path's history (\"image\" is the CPU path's)");
  foveation::ViewSettings vs =
      foveation::temporal_view_settings(eye.temporal, static_cast<int>(settings.rays_per_point), kSampleSeed);
  vs.reconstruct_on_cpu = !path.reconstruct_on_gpu;
  vs.content_density.full_contrast = content_contrast_for_path(settings, path.reconstruct_on_gpu);
  vs.content_density.rays_contrast = content_rays_for(settings);
  vs.content_density.rays_doubling_ecc_deg = content_rays_doubling_for(settings, eye.temporal);
  vs.content_density.exposure = settings.display.exposure;
  eye.view = std::make_unique<foveation::FoveatedView>(view_tables, vs, path.stages(view_tables, vs));
}

void FoveatedRenderer::Frames::aim_at_gaze(uint32_t e, const FrameGaze& frame_gaze, foveation::FrameRequest& request,
                                           XrFoveatedRendererStatsFOVEART* stats) {
  request.frame_index = frame_index;
  request.saccade = frame_gaze.valid && frame_gaze.saccade;
  request.blink = frame_gaze.valid && frame_gaze.blink;
  const foveation::EyeFrustum frustum = foveation::eye_frustum(request.view);
  request.gaze_px = foveation::lens_centre_px(frustum);
  if (!frame_gaze.valid || foveation::gaze_pixel(frustum, frame_gaze.direction_view[e], &request.gaze_px)) return;
  // A valid gaze behind the eye (or 87 degrees or more off its axis) projects nowhere: lens centre, flagged.
  ++input.gaze_behind_views;
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART;
  if (behind_once.first()) {
    const glm::vec3 d = frame_gaze.direction_view[e];
    log(LogLevel::Warn, "foveated renderer: eye ", e, ": the gaze points backwards or 87 degrees or more off the view "
        "axis (view-space direction ", d.x, ", ", d.y, ", ", d.z, "); foveating at the lens centre (logged once, "
        "counted in the stats)");
  }
}

bool FoveatedRenderer::Frames::run_frame(uint32_t e, const foveation::FrameRequest& request,
                                         const std::shared_ptr<const foveation::ViewTables>& view_tables,
                                         XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  foveation::FrameResources* resources = eye.path->resources(e, view_tables, stats);
  if (resources == nullptr) return false;
  return run_step(e, stats, [&] {
    return eye.view->render(request, settings.trace_rays, settings.user_data, *resources, executor);
  });
}

void FoveatedRenderer::Frames::frame_path_error(uint32_t e, const std::exception& error,
                                                XrFoveatedRendererStatsFOVEART* stats) {
  if (internal_once.first()) {
    log(LogLevel::Error, "foveated renderer: eye ", e, ": frame path error: ", error.what(),
        "; showing the app's own image for this view (logged once, counted in stats)");
  }
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
}

bool FoveatedRenderer::Frames::take_result(uint32_t e, const foveation::FrameResult& result,
                                           XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  stats->gazePixel[e] = XrVector2f{result.centre_px.x, result.centre_px.y};  // the foveation centre used
  stats->pointsPerEye[e] = result.points;
  stats->raysPerEye[e] = static_cast<uint32_t>(std::min<uint64_t>(result.rays, UINT32_MAX));
  stats->selectMs[e] = static_cast<float>(result.select_ms);
  stats->traceMs[e] = static_cast<float>(result.trace_ms);
  stats->reconstructMs[e] = static_cast<float>(result.reconstruct_ms);
  stats->temporalMs[e] = static_cast<float>(result.temporal_ms);
  stats->uploadMs[e] = static_cast<float>(result.encode_ms);  // the present adds the upload
  stats->callbackFailures += result.failed_batches;
  take_density(e, result);
  reconstruction.temporal_reset_last_frame[e] = result.temporal_reset;
  reconstruction.temporal_resets += result.temporal_reset ? 1 : 0;
  stats->invalidColours += result.invalid_colours;
  if (result.ok()) return true;
  if (result.failure == foveation::FrameFailure::resources_failed) {
    eye.path->resources_failed(e, result.message, stats);
    return false;
  }
  stats->fallbackFlags |= fallback_flag(result.failure);
  LogOnce& once = result.failure == foveation::FrameFailure::callback_failed ? callback_once : colour_once;
  if (once.first()) {
    log(LogLevel::Error, "foveated renderer: eye ", e, ": ", result.message,
        "; showing the app's own image for this view (logged once, counted in stats)");
  }
  return false;
}

// The CPU trace's content density cost (foveation::DensityCost): 0 on a device trace, whose
// passes are timed on the device and whose thinned points come with its status (apply_collected).
void FoveatedRenderer::Frames::take_density(uint32_t e, const foveation::FrameResult& result) {
  const std::optional<EyePath>& path = eyes[e].path;
  if (!path || !path->device_trace) density.points_thinned[e] = result.points_thinned;
  density.levels_ms[e] = static_cast<float>(result.density.levels_ms);
  density.test_ms[e] = static_cast<float>(result.density.test_ms);
  density.observe_ms[e] = static_cast<float>(result.density.observe_ms);
  density.fill_ms[e] = static_cast<float>(result.density.fill_ms);
}

foveation::FrameResources* FoveatedRenderer::Frames::gpu_resources(
    uint32_t e, const std::shared_ptr<const foveation::ViewTables>& view_tables, bool device_trace) {
  Eye& eye = eyes[e];
  eye.device = gpu::DeviceFrame{};
  eye.device.slot = uint32_t(frame_index % gpu::kFrameSlots);
  eye.device.srgb = eye.swapchain->srgb();
  eye.device.display = display;
  eye.device.begin = [this, e, view_tables, device_trace](gpu::DeviceFrame& frame, std::string* error) {
    return begin_on_gpu(e, view_tables, device_trace, frame, error);
  };
  return &eye.device;
}

foveation::FrameResources* FoveatedRenderer::Frames::cpu_resources(uint32_t e, XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  std::string error;
  eye.host.rgba8 = eye.swapchain->staging(&error);
  if (eye.host.rgba8 == nullptr) {
    upload_failed(e, error, stats);
    return nullptr;
  }
  eye.host.output = nullptr;  // set by this frame's history
  eye.host.srgb = eye.swapchain->srgb();
  eye.host.display = display;
  return &eye.host;
}

void FoveatedRenderer::Frames::fall_back_to_cpu(uint32_t e, const std::string& error,
                                                XrFoveatedRendererStatsFOVEART* stats) {
  // This frame shows the app's image; the CPU reconstructs from the next one.
  Eye& eye = eyes[e];
  eye.gpu_failed = true;
  eye.path.reset();  // chosen again at the next frame: the CPU's stages
  eye.gpu_eye = nullptr;  // kept by the frame in flight until it finished
  eye.gpu_tables = nullptr;
  ++reconstruction.gpu_fallbacks;
  if (gpu_once.first()) {
    log(LogLevel::Error, "foveated renderer: eye ", e, ": GPU reconstruction failed: ", error,
        "; this eye reconstructs on the CPU from the next frame (logged once, counted in the stats)");
  }
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
}

void FoveatedRenderer::Frames::upload_failed(uint32_t e, const std::string& error,
                                             XrFoveatedRendererStatsFOVEART* stats) {
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
  if (upload_once.first()) log(LogLevel::Error, "foveated renderer: eye ", e, ": upload failed: ", error);
}

bool FoveatedRenderer::Frames::present_gpu(uint32_t e, XrFoveatedRendererStatsFOVEART* stats) {
  auto& flight = in_flight[uint32_t(frame_index % gpu::kFrameSlots)][e];
  if (flight) flight->recorded = true;  // its status and times are read when the slot comes round
  apply_collected(e, stats);  // the GPU's times of an earlier frame of this eye
  reconstruction.path = XR_FOVEATED_RECONSTRUCTION_PATH_GPU_FOVEART;
  reconstruction.temporal = eyes[e].temporal;
  return true;
}

bool FoveatedRenderer::Frames::present_cpu(uint32_t e, XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  const auto t0 = Clock::now();
  std::string error;
  const bool uploaded = eye.swapchain->upload(&error);
  stats->uploadMs[e] += ms_since(t0);
  if (!uploaded) {
    upload_failed(e, error, stats);
    return false;
  }
  reconstruction.path = XR_FOVEATED_RECONSTRUCTION_PATH_CPU_FOVEART;
  reconstruction.temporal = eye.temporal;
  for (float* t : {reconstruction.gpu_scatter_ms, reconstruction.gpu_gather_ms, reconstruction.gpu_temporal_ms,
                   reconstruction.gpu_encode_ms, density.gpu_fill_ms, density.gpu_contrast_ms}) {
    t[e] = 0.0f;
  }
  return true;
}

bool FoveatedRenderer::Frames::view_traceable(uint32_t e, const FoveartEyeView& view, const char* where,
                                              XrFoveatedRendererStatsFOVEART* stats) {
  const std::string problem = foveation::eye_view_problem(view);
  if (problem.empty()) return true;
  // Forwarded as sent: the runtime judges the pose; no engine is handed a view it cannot trace.
  stats->fallbackFlags |= XR_FOVEATED_FALLBACK_INVALID_VIEW_BIT_FOVEART;
  if (view_once.first())
    log(LogLevel::Warn, where, ": eye ", e, ": its view cannot be traced: ", problem,
        "; forwarded as the app sent it, not ray traced (logged once, flagged in the stats)");
  return false;
}

bool FoveatedRenderer::Frames::render_eye(uint32_t e, const FrameGaze& frame_gaze, const FoveartEyeView& submitted,
                                          XrCompositionLayerProjectionView& view,
                                          XrFoveatedRendererStatsFOVEART* stats) {
  Eye& eye = eyes[e];
  if (eye.failed) {
    stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
    return false;
  }
  const uint32_t w = submitted.width_px, h = submitted.height_px;
  foveation::FrameRequest request;
  request.view = submitted;
  const Tables found = tables_for(request.view);
  if (found.failed || found.ready == nullptr) {
    stats->fallbackFlags |= found.failed ? XR_FOVEATED_FALLBACK_TABLES_FAILED_BIT_FOVEART
                                         : XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART;
    return false;
  }
  if (!ensure_swapchain(e, w, h, stats)) return false;
  // No path, or the app-recorded trace alone and no batch acquired for this frame.
  if ((!eye.path && !choose_path(e)) || (eye.path->device_trace && settings.trace_rays_device == nullptr)) {
    stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
    return false;
  }
  ensure_view(e, found.ready);
  aim_at_gaze(e, frame_gaze, request, stats);
  if (!run_frame(e, request, found.ready, stats)) return false;
  if (!eye.path->present(e, stats)) return false;
  show_layer_image(e, view);
  return true;
}

void FoveatedRenderer::Frames::show_layer_image(uint32_t e, XrCompositionLayerProjectionView& view) const {
  const EyeSwapchain& swapchain = *eyes[e].swapchain;
  view.subImage.swapchain = swapchain.handle();
  view.subImage.imageRect = {{0, 0}, {static_cast<int32_t>(swapchain.width_px()), static_cast<int32_t>(swapchain.height_px())}};
  view.subImage.imageArrayIndex = 0;
}

FoveatedRenderer::FoveatedRenderer(std::shared_ptr<SessionState> session, RendererSettings settings)
    : session_(std::move(session)), settings_(std::move(settings)) {
  stats_.type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  stats_.gazeSource = settings_.gaze_source;
  if (session_->has_vulkan) frames_ = std::make_unique<Frames>(session_, settings_, input_, reconstruction_, density_);
}

FoveatedRenderer::~FoveatedRenderer() = default;

uint32_t FoveatedRenderer::render(XrTime display_time, const XrCompositionLayerProjection& layer,
                                  XrCompositionLayerProjectionView* out_views, const std::vector<bool>& rect_valid,
                                  const XrFoveatedDisplayTransformFOVEART* display) {
  std::lock_guard lock(mutex_);
  if (frames_ == nullptr) {  // a session without Vulkan: every view is the app's
    stats_.framesFallback += layer.viewCount;
    stats_.fallbackFlags = XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
    return 0;
  }
  return frames_->render(display_time, layer, out_views, rect_valid, display, &stats_);
}

void FoveatedRenderer::count_foreign_session_layer() {
  ++input_.foreign_session_layers;
  if (foreign_once_.first()) {
    log(LogLevel::Warn, "xrEndFrame: a projection layer names a foveated renderer of another session; forwarded "
                        "as the app sent it, not ray traced (logged once, counted in that renderer's stats)");
  }
}

void FoveatedRenderer::stats(XrFoveatedRendererStatsFOVEART* out_stats) const {
  std::lock_guard lock(mutex_);
  void* next = out_stats->next;
  *out_stats = stats_;
  out_stats->type = XR_TYPE_FOVEATED_RENDERER_STATS_FOVEART;
  out_stats->next = next;
  // The input stats, wherever the app chained them; other structs are left alone.
  if (auto* in = find_in_out_chain<XrFoveatedRendererInputStatsFOVEART>(next,
                                                                       XR_TYPE_FOVEATED_RENDERER_INPUT_STATS_FOVEART)) {
    in->cacheFilesRejected = input_.cache_files_rejected;
    in->cacheFailures = input_.cache_failures;
    in->tableBuildsFailed = input_.table_builds_failed;
    in->tableSetsEvicted = input_.table_sets_evicted;
    in->tableSetsResident = input_.table_sets_resident;
    in->reserved = 0;
    in->gazeBehindViews = input_.gaze_behind_views;
    in->invalidImageRectViews = input_.invalid_image_rect_views;
    in->foreignSessionLayers = input_.foreign_session_layers;
  }
  if (auto* app = find_in_out_chain<XrFoveatedAppTraceStatsFOVEART>(next, XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART)) {
    void* app_next = app->next;
    *app = XrFoveatedAppTraceStatsFOVEART{};
    app->type = XR_TYPE_FOVEATED_APP_TRACE_STATS_FOVEART;
    app->next = app_next;
    if (frames_ != nullptr) frames_->app_trace_stats(app);
  }
  if (auto* out = find_in_out_chain<XrFoveatedRendererDensityStatsFOVEART>(next,
                                                                          XR_TYPE_FOVEATED_RENDERER_DENSITY_STATS_FOVEART)) {
    write_density_stats(out);
  }
  // The reconstruction path, temporal mode and GPU stage times.
  if (auto* rec = find_in_out_chain<XrFoveatedRendererReconstructionStatsFOVEART>(
          next, XR_TYPE_FOVEATED_RENDERER_RECONSTRUCTION_STATS_FOVEART)) {
    rec->path = reconstruction_.path;
    rec->temporal = xr_temporal(reconstruction_.temporal);
    rec->gpuFallbacks = reconstruction_.gpu_fallbacks;
    for (int e = 0; e < 2; ++e) {
      rec->gpuScatterMs[e] = reconstruction_.gpu_scatter_ms[e];
      rec->gpuGatherMs[e] = reconstruction_.gpu_gather_ms[e];
      rec->gpuTemporalMs[e] = reconstruction_.gpu_temporal_ms[e];
      rec->gpuEncodeMs[e] = reconstruction_.gpu_encode_ms[e];
      rec->temporalResetLastFrame[e] = reconstruction_.temporal_reset_last_frame[e] ? XR_TRUE : XR_FALSE;
    }
    rec->temporalResets = reconstruction_.temporal_resets;
    rec->gazeSaccadeLastFrame = reconstruction_.gaze_saccade_last_frame ? XR_TRUE : XR_FALSE;
    rec->gazeBlinkLastFrame = reconstruction_.gaze_blink_last_frame ? XR_TRUE : XR_FALSE;
  }
}

void FoveatedRenderer::write_density_stats(XrFoveatedRendererDensityStatsFOVEART* out) const {
  for (int e = 0; e < 2; ++e) {
    out->pointsThinned[e] = density_.points_thinned[e];
    out->levelsMs[e] = density_.levels_ms[e];
    out->testMs[e] = density_.test_ms[e];
    out->observeMs[e] = density_.observe_ms[e];
    out->fillMs[e] = density_.fill_ms[e];
    out->gpuFillMs[e] = density_.gpu_fill_ms[e];
    out->gpuContrastMs[e] = density_.gpu_contrast_ms[e];
  }
}

}  // namespace foveart::layer
