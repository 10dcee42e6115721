#include "gaze_source.hpp"

#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#ifdef FOVEART_LAYER_HAS_GAZE
#include "gaze_provider/gaze_provider.h"
#endif

namespace foveart::layer {
namespace {

class NoGaze final : public GazeSource {
 public:
  FrameGaze at(int64_t, int64_t) override { return {}; }
};

#ifdef FOVEART_LAYER_HAS_GAZE
// FOVE head space (+z forward, +y up, +x right) -> OpenXR view space (-z forward).
glm::vec3 to_view(const gaze::Vec3f& d) { return glm::normalize(glm::vec3(d.x, d.y, -d.z)); }

bool usable(const gaze::Vec3f& d) {
  return std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) && d.z > 0.05f;
}

class ProviderGaze final : public GazeSource {
 public:
  explicit ProviderGaze(std::unique_ptr<gaze::GazeProvider> provider) : provider_(std::move(provider)) {}
  ~ProviderGaze() override { provider_->stop(); }

  FrameGaze at(int64_t display_time_ns, int64_t now_ns) override {
    FrameGaze out;
    out.source = XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
    const auto sample = provider_->sample_at(display_time_ns);
    if (!sample || !sample->valid || sample->lost || !usable(sample->combined_direction)) return out;
    const gaze::EyeGaze* eyes[2] = {&sample->left, &sample->right};
    for (int e = 0; e < 2; ++e) {
      const gaze::Vec3f& d = eyes[e]->valid && usable(eyes[e]->direction) ? eyes[e]->direction
                                                                          : sample->combined_direction;
      out.direction_view[e] = to_view(d);
    }
    const auto newest = provider_->latest();
    out.age_ms = newest ? static_cast<float>(static_cast<double>(now_ns - newest->host_time_ns) * 1e-6) : 0.0f;
    out.valid = true;
    return out;
  }

 private:
  std::unique_ptr<gaze::GazeProvider> provider_;
};
#endif

}  // namespace

std::unique_ptr<GazeSource> create_gaze_source(const RendererSettings& settings, std::string* out_warning) {
  switch (settings.gaze_source) {
    case XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART: {
#ifdef FOVEART_LAYER_HAS_GAZE
      auto created = gaze::create_gaze_provider(settings.gaze_provider_spec);
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
      return std::make_unique<ProviderGaze>(std::move(created.provider));
#else
      *out_warning = "this build has no gaze provider; fixed foveation at the lens centre";
      return std::make_unique<NoGaze>();
#endif
    }
    case XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART:
      *out_warning = "gaze source XR_EXT_eye_gaze_interaction is not implemented yet; fixed foveation at the "
                     "lens centre";
      return std::make_unique<NoGaze>();
    default:
      return std::make_unique<NoGaze>();
  }
}

}  // namespace foveart::layer
