#include "renderer.hpp"

#include <cmath>
#include <cstdint>

#include "log.hpp"
#include "next_chain.hpp"

namespace foveart::layer {
namespace {

XrFoveatedInterpolationFOVEART interpolation_from_name(const std::string& name) {
  if (name == "nearest") return XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART;
  if (name == "rbf") return XR_FOVEATED_INTERPOLATION_RBF_FOVEART;
  return XR_FOVEATED_INTERPOLATION_MSM_FOVEART;
}

XrFoveatedGazeSourceFOVEART gaze_source_from_name(const std::string& name) {
  if (name == "none") return XR_FOVEATED_GAZE_SOURCE_NONE_FOVEART;
  if (name == "eye_gaze_interaction") return XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART;
  return XR_FOVEATED_GAZE_SOURCE_PROVIDER_FOVEART;
}

// The traces chained into the create info: a device trace, the app-recorded trace.
bool resolve_chained_traces(const XrFoveatedRendererCreateInfoFOVEART& info, RendererSettings* out,
                            std::string* error) {
  RendererSettings& s = *out;
  if (const auto* device = find_in_chain<XrFoveatedDeviceTraceInfoFOVEART>(info.next,
                                                                          XR_TYPE_FOVEATED_DEVICE_TRACE_INFO_FOVEART)) {
    if (device->traceRaysDevice == nullptr) {
      *error = "XrFoveatedDeviceTraceInfoFOVEART::traceRaysDevice must not be NULL";
      return false;
    }
    s.trace_rays_device = device->traceRaysDevice;
    s.device_user_data = device->userData;
  }
  if (const auto* app = find_in_chain<XrFoveatedAppTraceInfoFOVEART>(info.next, XR_TYPE_FOVEATED_APP_TRACE_INFO_FOVEART)) {
    if (app->queueFamilyIndexCount > 0 && app->queueFamilyIndices == nullptr) {
      *error = "XrFoveatedAppTraceInfoFOVEART::queueFamilyIndices is NULL with a nonzero queueFamilyIndexCount";
      return false;
    }
    s.app_trace = true;
    s.app_queue_families.assign(app->queueFamilyIndices, app->queueFamilyIndices + app->queueFamilyIndexCount);
  }
  return true;
}

}  // namespace

bool resolve_settings(const XrFoveatedRendererCreateInfoFOVEART& info, const LayerConfig& config,
                      RendererSettings* out, std::string* error) {
  RendererSettings s;
  s.interpolation = interpolation_from_name(config.interpolation);
  s.k = config.k;
  s.density_scale = config.density_scale;
  s.content_contrast = config.content_contrast;
  s.content_rays = config.content_rays;
  s.content_rays_doubling_deg = config.content_rays_doubling_deg;
  s.rays_per_point = config.rays_per_point;
  if (foveation::TemporalMode mode{}; foveation::parse_temporal_mode(config.temporal, &mode)) s.temporal = mode;
  s.gaze_source = gaze_source_from_name(config.gaze_source);
  s.gaze_provider_spec = config.gaze_provider;
  s.gaze_clock_display_time = config.gaze_clock == "display_time";
  s.threads = config.threads;
  s.cache_dir = config.cache_dir;
  s.wait_for_tables = config.wait_for_tables;
  s.reconstruction = config.reconstruction;
  s.display.exposure = config.exposure;
  s.display.tone_map = foveation::parse_tone_map(config.tone_map).value_or(foveation::ToneMap::pbr_neutral);

  if (!resolve_chained_traces(info, &s, error)) return false;
  if (info.traceRays == nullptr && s.trace_rays_device == nullptr && !s.app_trace) {
    *error = "traceRays must not be NULL (unless an XrFoveatedDeviceTraceInfoFOVEART or XrFoveatedAppTraceInfoFOVEART "
             "is chained)";
    return false;
  }
  s.trace_rays = info.traceRays;
  s.user_data = info.userData;
  if (info.interpolation != XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART) {
    if (static_cast<uint64_t>(info.interpolation) > XR_FOVEATED_INTERPOLATION_RBF_FOVEART) {
      *error = "interpolation " + std::to_string(info.interpolation) +
                   " is not an XrFoveatedInterpolationFOVEART (or XR_FOVEATED_INTERPOLATION_USE_CONFIG_FOVEART)";
      return false;
    }
    s.interpolation = info.interpolation;
  }
  if (info.k > 20) {
    *error = "k = " + std::to_string(info.k) + " is outside 1..20 (0 = config default)";
    return false;
  }
  if (info.k != 0) s.k = info.k;
  if (s.interpolation == XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART) s.k = 1;
  if (!std::isfinite(info.densityScale) || info.densityScale < 0.0f || info.densityScale > 16.0f) {
    *error = "densityScale must be in (0, 16] (0 = config default)";
    return false;
  }
  if (info.densityScale != 0.0f) s.density_scale = info.densityScale;
  if (info.raysPerPoint > 64) {
    *error = "raysPerPoint = " + std::to_string(info.raysPerPoint) + " is outside 1..64 (0 = config default)";
    return false;
  }
  if (info.raysPerPoint != 0) s.rays_per_point = info.raysPerPoint;
  if (info.temporal != XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART) {
    foveation::TemporalMode mode{};
    if (!temporal_mode_of(info.temporal, &mode)) {
      *error = "temporal " + std::to_string(info.temporal) +
                   " is not an XrFoveatedTemporalFOVEART (or XR_FOVEATED_TEMPORAL_USE_CONFIG_FOVEART)";
      return false;
    }
    s.temporal = mode;
  }
  if (info.gazeSource != XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART) {
    if (static_cast<uint64_t>(info.gazeSource) > XR_FOVEATED_GAZE_SOURCE_EYE_GAZE_INTERACTION_FOVEART) {
      *error = "gazeSource " + std::to_string(info.gazeSource) +
                   " is not an XrFoveatedGazeSourceFOVEART (or XR_FOVEATED_GAZE_SOURCE_USE_CONFIG_FOVEART)";
      return false;
    }
    s.gaze_source = info.gazeSource;
  }
  if (info.gazeProviderSpec != nullptr && info.gazeProviderSpec[0] != '\0') s.gaze_provider_spec = info.gazeProviderSpec;
  *out = std::move(s);
  return true;
}

bool temporal_mode_of(XrFoveatedTemporalFOVEART value, foveation::TemporalMode* out) {
  for (foveation::TemporalMode m :
       {foveation::TemporalMode::off, foveation::TemporalMode::image, foveation::TemporalMode::rays}) {
    if (xr_temporal(m) == value) {
      *out = m;
      return true;
    }
  }
  return false;
}

XrFoveatedTemporalFOVEART xr_temporal(foveation::TemporalMode mode) {
  switch (mode) {
    case foveation::TemporalMode::off: return XR_FOVEATED_TEMPORAL_OFF_FOVEART;
    case foveation::TemporalMode::image: return XR_FOVEATED_TEMPORAL_IMAGE_FOVEART;
    case foveation::TemporalMode::rays: return XR_FOVEATED_TEMPORAL_RAYS_FOVEART;
  }
  return XR_FOVEATED_TEMPORAL_OFF_FOVEART;
}

float content_contrast_for_path(const RendererSettings& settings, bool reconstruct_on_gpu) {
  return settings.content_contrast.value_or(reconstruct_on_gpu ? kDeviceContentContrast : 0.0f);
}

float content_rays_for(const RendererSettings& settings) {
  return settings.content_rays.value_or(
      foveation::default_rays_contrast(int(settings.rays_per_point), settings.density_scale));
}

float content_rays_doubling_for(const RendererSettings& settings, foveation::TemporalMode temporal) {
  return settings.content_rays_doubling_deg.value_or(foveation::default_rays_doubling_ecc_deg(temporal));
}

foveation::TemporalMode temporal_for_path(const RendererSettings& settings, bool reconstruct_on_gpu) {
  return settings.temporal.value_or(reconstruct_on_gpu ? foveation::TemporalMode::rays : foveation::TemporalMode::image);
}

}  // namespace foveart::layer
