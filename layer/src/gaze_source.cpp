#include "gaze_source.hpp"

#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "xr_glm.hpp"
#include "log.hpp"
#include "state.hpp"

#include "gaze_provider/backends.h"
#include "gaze_provider/gaze_provider.h"
#include "gaze_provider/onset_latch.h"
#include "gaze_provider/stepped_clock.h"

namespace foveart::layer {
namespace {

class NoGaze final : public GazeSource {
 public:
  FrameGaze at(const GazeQuery&) override { return {}; }
};

// XR_EXT_eye_gaze_interaction: the gaze pose located in the projection layer's
// space at display time; its -z axis, seen from each eye's view pose, is that
// eye's gaze direction (fixation at infinity, as the provider path assumes).
class EyeGazeInteraction final : public GazeSource {
 public:
  explicit EyeGazeInteraction(std::shared_ptr<SessionEyeGaze> session) : session_(std::move(session)) {}

  FrameGaze at(const GazeQuery& q) override {
    FrameGaze out;
    out.source = XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART;
    const auto gaze = session_->locate(q.space, q.display_time);
    if (!gaze.valid) {
      if (gaze.problem != last_problem_) {  // once per change, not per frame
        log(LogLevel::Info, "XR_EXT_eye_gaze_interaction: ", gaze.problem, "; fixed foveation at the lens centre");
        last_problem_ = gaze.problem;
      }
      return out;
    }
    last_problem_.clear();
    const glm::vec3 forward = to_glm(gaze.pose_in_space.orientation) * glm::vec3(0.0f, 0.0f, -1.0f);
    for (uint32_t e = 0; e < 2 && e < q.view_count; ++e) {
      const glm::quat eye = glm::normalize(to_glm(q.views[e].pose.orientation));
      out.direction_view[e] = glm::normalize(glm::conjugate(eye) * forward);
    }
    if (gaze.sample_time != 0) {
      // Age at composition; under a virtual runtime clock, at display time.
      const int64_t now = q.runtime_clock_is_steady ? q.now_ns : q.display_time;
      out.age_ms = static_cast<float>(static_cast<double>(now - gaze.sample_time) * 1e-6);
    }
    out.valid = q.view_count > 0;
    return out;
  }

 private:
  std::shared_ptr<SessionEyeGaze> session_;
  std::string last_problem_;
};

// FOVE head space (+z forward, +y up, +x right) -> OpenXR view space (-z forward).
glm::vec3 to_view(const gaze::Vec3f& d) { return glm::normalize(glm::vec3(d.x, d.y, -d.z)); }

// A direction the frame can use: finite and not zero. One pointing backwards is
// usable: the frame foveates it at the lens centre and flags it (not "no gaze").
bool usable(const gaze::Vec3f& d) {
  return std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f);
}

class ProviderGaze final : public GazeSource {
 public:
  // stepped: the provider's clock, stepped here to each frame's display time; null: the
  // provider runs on its own (steady) clock.
  ProviderGaze(std::unique_ptr<gaze::GazeProvider> provider, std::shared_ptr<gaze::SteppedClock> stepped)
      : provider_(std::move(provider)), stepped_(std::move(stepped)) {}
  ~ProviderGaze() override {
    if (stepped_) stepped_->release();  // stop() returns without time passing
    provider_->stop();
  }

  FrameGaze at(const GazeQuery& q) override {
    FrameGaze out;
    out.source = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
    int64_t now_ns = q.now_ns, target_ns = q.steady_display_time_ns();
    if (stepped_) now_ns = target_ns = step_to(q.display_time);
    const auto sample = provider_->sample_at(target_ns);
    if (!sample || !sample->valid || sample->lost || !usable(sample->combined_direction)) return out;
    const gaze::EyeGaze* eyes[2] = {&sample->left, &sample->right};
    for (int e = 0; e < 2; ++e) {
      const gaze::Vec3f& d = eyes[e]->valid && usable(eyes[e]->direction) ? eyes[e]->direction
                                                                          : sample->combined_direction;
      out.direction_view[e] = to_view(d);
    }
    const auto newest = provider_->latest();
    out.age_ms = newest ? static_cast<float>(static_cast<double>(now_ns - newest->host_time_ns) * 1e-6) : 0.0f;
    // A saccade or blink that began and ended between two frames counts for the next.
    const gaze::OnsetLatch::Began began = newest ? onsets_.update(*newest) : gaze::OnsetLatch::Began{};
    out.saccade = sample->in_saccade || began.saccade;
    out.blink = sample->held || began.hold;
    out.valid = true;
    return out;
  }

 private:
  // Lets the provider produce every sample due by this frame's display time (the first
  // frame's is the clock's zero); returns the clock's time.
  int64_t step_to(XrTime display_time) {
    if (!origin_) origin_ = display_time;
    const auto stopped = [&] {
      const gaze::ProviderState state = provider_->status().state;
      return state == gaze::ProviderState::ended || state == gaze::ProviderState::stopped;
    };
    if (!stepped_->run_until(display_time - *origin_, stopped) && stall_once_.first()) {
      log(LogLevel::Warn, "gaze provider: its thread did not settle at the frame's display time within ",
          gaze::SteppedClock::kGuard.count(), " s (\"gaze_clock\": \"display_time\"); the frame uses the newest "
          "sample (logged once)");
    }
    return stepped_->now_ns();
  }

  std::unique_ptr<gaze::GazeProvider> provider_;
  std::shared_ptr<gaze::SteppedClock> stepped_;
  std::optional<XrTime> origin_;
  LogOnce stall_once_;
  gaze::OnsetLatch onsets_;
};

}  // namespace

std::unique_ptr<GazeSource> create_gaze_source(const RendererSettings& settings, const SessionState& session,
                                               std::string* out_warning,
                                               std::shared_ptr<gaze::HostClock> provider_clock) {
  switch (settings.gaze_source) {
    case XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART: {
      gaze::ProviderOptions options;
      std::shared_ptr<gaze::SteppedClock> stepped;
      if (!provider_clock && settings.gaze_clock_display_time) provider_clock = stepped = std::make_shared<gaze::SteppedClock>(0);
      options.clock = std::move(provider_clock);
      auto created = gaze::create_gaze_provider(settings.gaze_provider_spec, options);
      if (!created) {
        *out_warning = "gaze provider '" + settings.gaze_provider_spec + "': " + created.error +
                       "; fixed foveation at the lens centre";
        return std::make_unique<NoGaze>();
      }
      std::string error;
      if (!created.provider->start(&error)) {
        *out_warning = "gaze provider '" + settings.gaze_provider_spec + "' did not start: " + error +
                       "; fixed foveation at the lens centre";
        return std::make_unique<NoGaze>();
      }
      return std::make_unique<ProviderGaze>(std::move(created.provider), std::move(stepped));
    }
    case XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART: {
      const auto& actions = session.instance->eye_gaze;
      if (!actions.ready() || session.eye_gaze == nullptr) {
        *out_warning = "gaze source XR_EXT_eye_gaze_interaction unavailable: " +
                       (actions.unavailable_reason.empty() ? std::string("the layer's gaze action could not be set up")
                                                           : actions.unavailable_reason) +
                       "; fixed foveation at the lens centre";
        return std::make_unique<NoGaze>();
      }
      XrSystemEyeGazeInteractionPropertiesEXT eye{XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT, nullptr, XR_FALSE};
      XrSystemProperties props{XR_TYPE_SYSTEM_PROPERTIES, &eye, XR_NULL_SYSTEM_ID, 0, {}, {}, {}};
      const XrResult r = session.instance->next.GetSystemProperties(session.instance->handle, session.system_id, &props);
      if (XR_FAILED(r) || eye.supportsEyeGazeInteraction != XR_TRUE) {
        *out_warning = "gaze source XR_EXT_eye_gaze_interaction: the system reports no eye tracking "
                       "(supportsEyeGazeInteraction = XR_FALSE); fixed foveation at the lens centre";
        return std::make_unique<NoGaze>();
      }
      return std::make_unique<EyeGazeInteraction>(session.eye_gaze);
    }
    default:
      return std::make_unique<NoGaze>();
  }
}

}  // namespace foveart::layer
