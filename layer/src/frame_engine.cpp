#include "frame_engine.hpp"

#include "log.hpp"

#ifdef FOVEART_LAYER_HAS_FOVEATION
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <map>
#include <tuple>

#include "eye_math.hpp"
#include "eye_swapchain.hpp"
#include "foveation/point_set_cache.hpp"
#include "gaze_source.hpp"
#include "view_pipeline.hpp"
#include "worker_pool.hpp"
#endif

namespace foveart::layer {

#ifndef FOVEART_LAYER_HAS_FOVEATION

std::unique_ptr<FrameEngine> FrameEngine::create(std::shared_ptr<SessionState>, const RendererSettings&) {
  log(LogLevel::Warn, "foveated renderer: this build has no foveation core; views pass through");
  return nullptr;
}

#else

namespace {

using Clock = std::chrono::steady_clock;
float ms_since(Clock::time_point t0) { return std::chrono::duration<float, std::milli>(Clock::now() - t0).count(); }

std::filesystem::path cache_dir(const RendererSettings& settings) {
  if (!settings.cache_dir.empty()) return settings.cache_dir;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && x[0] != '\0') {
    return std::filesystem::path(x) / "foveart";
  }
  if (const char* h = std::getenv("HOME"); h != nullptr && h[0] != '\0') {
    return std::filesystem::path(h) / ".cache" / "foveart";
  }
  return std::filesystem::temp_directory_path() / "foveart";
}

int64_t steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// Per-eye state: the layer's swapchain and the CPU pipeline.
struct Eye {
  std::unique_ptr<EyeSwapchain> swapchain;
  std::unique_ptr<ViewPipeline> pipeline;
  bool failed = false;  // swapchain creation failed: fall back for good
};

class FoveatedFrameEngine final : public FrameEngine {
 public:
  FoveatedFrameEngine(std::shared_ptr<SessionState> session, const RendererSettings& settings)
      : session_(std::move(session)), settings_(settings), pool_(settings.worker_threads) {
    std::string warning;
    gaze_ = create_gaze_source(settings_, *session_, &warning);
    if (!warning.empty()) log(LogLevel::Warn, "foveated renderer: ", warning);
  }

  ~FoveatedFrameEngine() override {
    for (auto& [key, slot] : tables_) {
      if (slot.pending.valid()) slot.pending.wait();
    }
  }

  uint32_t render(XrTime display_time, const XrCompositionLayerProjection& layer,
                  XrCompositionLayerProjectionView* out_views, XrFoveatedRendererStatsFOVEART* stats) override {
    ++frame_index_;
    // XrTime on Linux runtimes is CLOCK_MONOTONIC (= steady_clock); a clock far
    // away (virtual runtime clock) is replaced by now for gaze prediction.
    const int64_t now_ns = steady_now_ns();
    const bool steady = std::llabs(display_time - now_ns) < 1'000'000'000;
    GazeQuery query;
    query.now_ns = now_ns;
    query.display_time = display_time;
    query.runtime_clock_is_steady = steady;
    query.space = layer.space;
    query.views = out_views;
    query.view_count = layer.viewCount;
    const FrameGaze gaze = gaze_->at(query);
    stats->gazeSource = gaze.valid ? gaze.source : XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
    stats->gazeAgeMs = gaze.valid ? gaze.age_ms : 0.0f;
    stats->fallbackFlags = gaze.valid ? 0 : XR_FOVEATED_FALLBACK_FIXED_FOVEATION_BIT_FOVEART;
    if (!gaze.valid) ++stats->gazeLostFrames;

    uint32_t rewritten = 0;
    const uint32_t views = std::min<uint32_t>(layer.viewCount, 2);
    for (uint32_t e = 0; e < views; ++e) {
      if (render_eye(e, gaze, out_views[e], stats)) ++rewritten;
      else ++stats->framesFallback;
    }
    stats->framesFallback += layer.viewCount - views;  // views beyond two stay the app's
    if (rewritten > 0) ++stats->framesTraced;
    return rewritten;
  }

 private:
  using TableKey = std::tuple<uint32_t, uint32_t, int64_t>;  // w, h, horizontal FOV in micro-radians
  struct TableSlot {
    std::future<std::shared_ptr<const ViewTables>> pending;  // valid while building
    std::shared_ptr<const ViewTables> ready;
  };

  std::shared_ptr<const ViewTables> tables_for(uint32_t w, uint32_t h, const XrFovf& fov) {
    const double fov_rad = static_cast<double>(fov.angleRight) - static_cast<double>(fov.angleLeft);
    const TableKey key{w, h, std::llround(fov_rad * 1e6)};
    auto it = tables_.find(key);
    if (it == tables_.end()) {
      foveation::PointSetKey psk;
      psk.display = foveation::DisplayModel::from_fov(static_cast<int>(w), static_cast<int>(h), fov_rad * 180.0 / 3.14159265358979323846);
      psk.display.scale = static_cast<double>(settings_.density_scale);
      psk.seed = 1;
      psk.k = neighbor_count(settings_);
      const auto dir = cache_dir(settings_);
      log(LogLevel::Info, "foveated renderer: preparing tables for ", w, "x", h, " (cache ", dir.string(), ")");
      auto future = std::async(std::launch::async, [psk, dir, settings = settings_]() -> std::shared_ptr<const ViewTables> {
        try {
          std::error_code ec;
          std::filesystem::create_directories(dir, ec);
          return load_view_tables(psk, settings, dir);
        } catch (const std::exception& e) {
          log(LogLevel::Error, "foveated renderer: cannot build the foveation tables: ", e.what());
          return nullptr;
        }
      });
      it = tables_.emplace(key, TableSlot{std::move(future), nullptr}).first;
    }
    TableSlot& slot = it->second;
    if (slot.pending.valid()) {
      if (!settings_.wait_for_tables && slot.pending.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
        return nullptr;  // warming up
      }
      slot.ready = slot.pending.get();  // null when the build failed: fallback for good
    }
    return slot.ready;
  }

  bool render_eye(uint32_t e, const FrameGaze& gaze, XrCompositionLayerProjectionView& view,
                  XrFoveatedRendererStatsFOVEART* stats) {
    Eye& eye = eyes_[e];
    if (eye.failed) {
      stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
      return false;
    }
    const auto extent = view.subImage.imageRect.extent;
    if (extent.width <= 0 || extent.height <= 0) return false;
    const auto w = static_cast<uint32_t>(extent.width);
    const auto h = static_cast<uint32_t>(extent.height);
    auto tables = tables_for(w, h, view.fov);
    if (tables == nullptr) {
      stats->fallbackFlags |= XR_FOVEATED_FALLBACK_WARMING_UP_BIT_FOVEART;
      return false;
    }
    if (eye.swapchain == nullptr || eye.swapchain->width_px() != w || eye.swapchain->height_px() != h) {
      std::string error;
      eye.swapchain = EyeSwapchain::create(*session_, w, h, &error);
      if (eye.swapchain == nullptr) {
        log(LogLevel::Error, "foveated renderer: eye ", e, ": cannot create the layer's swapchain: ", error,
            "; this eye shows the app's image from now on");
        eye.failed = true;
        stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
        return false;
      }
      eye.pipeline.reset();
    }
    if (eye.pipeline == nullptr) eye.pipeline = std::make_unique<ViewPipeline>(tables);

    ViewRequest request;
    request.eye_index = e;
    request.frame_index = frame_index_;
    request.pose = view.pose;
    request.fov = view.fov;
    request.width_px = w;
    request.height_px = h;
    const EyeFrustum frustum = EyeFrustum::from(view.fov, static_cast<float>(w), static_cast<float>(h));
    request.gaze_px = frustum.centre_px();
    if (gaze.valid && gaze.direction_view[e].z < -0.05f) {
      request.gaze_px = frustum.pixel_of(gaze.direction_view[e]);
    }
    request.gaze_px = glm::round(request.gaze_px);
    stats->gazePixel[e] = XrVector2f{request.gaze_px.x, request.gaze_px.y};

    ViewOutcome outcome;
    try {
      outcome = eye.pipeline->render(request, settings_, pool_, eye.swapchain->staging(), eye.swapchain->srgb());
    } catch (const std::exception& error) {  // a table/gaze inconsistency: this view falls back
      outcome.ok = false;
      outcome.failure = XR_FOVEATED_FALLBACK_UNAVAILABLE_BIT_FOVEART;
      outcome.message = std::string("frame path error: ") + error.what();
    }
    stats->pointsPerEye[e] = outcome.points;
    stats->raysPerEye[e] = outcome.rays;
    stats->selectMs[e] = outcome.select_ms;
    stats->traceMs[e] = outcome.trace_ms;
    stats->interpolateMs[e] = outcome.interpolate_ms;
    stats->taaMs[e] = outcome.taa_ms;
    stats->callbackFailures += outcome.callback_failures;
    stats->invalidColours += outcome.invalid_colours;
    if (!outcome.ok) {
      stats->fallbackFlags |= outcome.failure;
      LogOnce& once = (outcome.failure & XR_FOVEATED_FALLBACK_CALLBACK_FAILED_BIT_FOVEART) ? callback_once_
                      : (outcome.failure & XR_FOVEATED_FALLBACK_INVALID_COLOUR_BIT_FOVEART) ? colour_once_
                                                                                            : internal_once_;
      if (once.first()) {
        log(LogLevel::Error, "foveated renderer: eye ", e, ": ", outcome.message,
            "; showing the app's own image for this view (logged once, counted in stats)");
      }
      return false;
    }
    const auto t0 = Clock::now();
    std::string error;
    const bool uploaded = eye.swapchain->upload(&error);
    stats->uploadMs[e] = ms_since(t0);
    if (!uploaded) {
      stats->fallbackFlags |= XR_FOVEATED_FALLBACK_UPLOAD_FAILED_BIT_FOVEART;
      if (upload_once_.first()) log(LogLevel::Error, "foveated renderer: eye ", e, ": upload failed: ", error);
      return false;
    }
    view.subImage.swapchain = eye.swapchain->handle();
    view.subImage.imageRect = {{0, 0}, {static_cast<int32_t>(w), static_cast<int32_t>(h)}};
    view.subImage.imageArrayIndex = 0;
    return true;
  }

  std::shared_ptr<SessionState> session_;
  RendererSettings settings_;
  WorkerPool pool_;
  std::unique_ptr<GazeSource> gaze_;
  std::map<TableKey, TableSlot> tables_;
  Eye eyes_[2];
  uint64_t frame_index_ = 0;
  LogOnce callback_once_, colour_once_, upload_once_, internal_once_;
};

}  // namespace

std::unique_ptr<FrameEngine> FrameEngine::create(std::shared_ptr<SessionState> session,
                                                 const RendererSettings& settings) {
  if (!session->has_vulkan) return nullptr;
  return std::make_unique<FoveatedFrameEngine>(std::move(session), settings);
}

#endif

}  // namespace foveart::layer
