// The view a render's options describe (render_options.hpp): preset geometry,
// the eye view, the foveated display and its tables, and the options' checks.
#include <render_view/render_options.hpp>


#include <engine/exposure.hpp>
#include <engine/render.hpp>
#include <foveation/content_density.hpp>
#include <foveation/executor.hpp>
#include <foveation/eye_view_check.hpp>
#include <foveation/executor.hpp>
#include <toolkit/format.hpp>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <numbers>
#include <vector>
#include <utility>

namespace foveart::render_view {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Per-eye size and symmetric frustum of a display preset.
struct PresetGeometry {
  int width_px = 0;
  int height_px = 0;
  double half_fov_x_rad = 0.0;
  double half_fov_y_rad = 0.0;
};

std::optional<PresetGeometry> preset_geometry(const std::string& preset) {
  const std::optional<foveation::DisplayModel> d = foveation::display_preset(preset);
  if (!d || !d->validate().empty()) return std::nullopt;
  // Pinhole: D pixels from the eye, the image spans +-W/2 and +-H/2.
  return PresetGeometry{d->width_px, d->height_px, std::atan(0.5 * d->width_px / d->view_distance_px),
                        std::atan(0.5 * d->height_px / d->view_distance_px)};
}

}  // namespace

// The display the foveated view's tables are built for: the preset's; for
// another size, the preset's horizontal FOV at that size; for another field of
// view (--fov-deg), the display the layer builds for that view (display_of_view).
std::optional<foveation::DisplayModel> foveated_display(const RenderOptions& o, const FoveartEyeView& view,
                                                        std::string* error) {
  std::optional<foveation::DisplayModel> display = foveation::display_preset(o.preset);
  if (!display) {
    *error = "unknown display preset '" + o.preset + "'";
    return std::nullopt;
  }
  if (o.fov.given()) {
    display = foveation::display_of_view(view);
  } else if (static_cast<uint32_t>(display->width_px) != view.width_px ||
             static_cast<uint32_t>(display->height_px) != view.height_px) {
    display = foveation::DisplayModel::from_fov(static_cast<int>(view.width_px), static_cast<int>(view.height_px),
                                                display->horizontal_fov_deg());
  }
  display->scale = o.density_scale;
  // The preset's pattern unless one is asked for (from_fov and display_of_view give the default).
  display->fovea_pattern = foveation::display_preset(o.preset)->fovea_pattern;
  if (!o.pattern.empty()) display->fovea_pattern = *foveation::parse_fovea_pattern(o.pattern);
  if (std::string bad = display->validate(); !bad.empty()) {
    *error = "display: " + bad;
    return std::nullopt;
  }
  return display;
}

foveation::ViewSettings foveated_view_settings(const RenderOptions& o) {
  foveation::ViewSettings vs = foveation::temporal_view_settings(o.temporal, o.rays_per_point, o.seed);
  vs.pixel_filter = o.pixel_filter;
  vs.content_density.full_contrast = float(o.content_contrast);
  vs.content_density.rays_contrast = float(content_rays_of(o));
  vs.content_density.rays_doubling_ecc_deg = float(content_rays_doubling_of(o));
  return vs;
}

double content_rays_of(const RenderOptions& o) {
  return o.content_rays.value_or(foveation::default_rays_contrast(o.rays_per_point, o.density_scale));
}

double content_rays_doubling_of(const RenderOptions& o) {
  return o.content_rays_doubling_deg.value_or(foveation::default_rays_doubling_ecc_deg(o.temporal));
}

int reconstruction_k(const RenderOptions& o) {
  return o.interpolation == "nearest" ? 1 : (o.k > 0 ? o.k : 5);
}

std::shared_ptr<const foveation::ViewTables> load_foveated_tables(const RenderOptions& o, const FoveartEyeView& view,
                                                                  const std::optional<std::filesystem::path>& cache_dir,
                                                                  foveation::Executor& executor,
                                                                  const foveation::LogFn& log, std::string* error) {
  const std::optional<foveation::DisplayModel> display = foveated_display(o, view, error);
  if (!display) return nullptr;
  foveation::PointSetKey key;
  key.display = *display;
  key.seed = o.seed;
  foveation::InterpOptions interp;
  interp.method = *foveation::parse_method(o.interpolation);
  interp.k = reconstruction_k(o);
  try {
    return foveation::load_view_tables(cache_dir, key, interp, executor, std::nullopt, {}, log);
  } catch (const std::exception& e) {
    *error = std::string("tables: ") + e.what();
    return nullptr;
  }
}

// Per-eye view of the preset (square pixels, symmetric frustum), optionally resized
// keeping the horizontal field of view or given another (--fov-deg H); or, with
// --fov-deg L,R,U,D / --pose, exactly the given OpenXR view.
FoveartEyeView eye_view(const RenderOptions& o, const engine::Scene& scene) {
  const PresetGeometry g = *preset_geometry(o.preset);
  const auto vec3_of = [](const std::optional<std::array<double, 3>>& a) -> std::optional<glm::vec3> {
    if (!a) return std::nullopt;
    return glm::vec3(float((*a)[0]), float((*a)[1]), float((*a)[2]));
  };
  const engine::Camera head = engine::standing_viewer(engine::scene_head(scene), vec3_of(o.viewer_m), vec3_of(o.look_at_m));
  FoveartEyeView view = engine::fove_eye_view(o.eye == "right" ? 1u : 0u, head);
  view.width_px = static_cast<uint32_t>(o.size_px ? o.size_px->x : g.width_px);
  view.height_px = static_cast<uint32_t>(o.size_px ? o.size_px->y : g.height_px);
  const double half_x = o.fov.horizontal ? 0.5 * *o.fov.horizontal * kPi / 180.0 : g.half_fov_x_rad;
  const double tan_x = std::tan(half_x);
  const double tan_y =
      o.size_px || o.fov.horizontal ? tan_x * view.height_px / view.width_px : std::tan(g.half_fov_y_rad);
  view.angle_left_rad = static_cast<float>(-half_x);
  view.angle_right_rad = static_cast<float>(half_x);
  view.angle_up_rad = static_cast<float>(std::atan(tan_y));
  view.angle_down_rad = static_cast<float>(-std::atan(tan_y));
  if (o.fov.angles) {
    float* angles[4] = {&view.angle_left_rad, &view.angle_right_rad, &view.angle_up_rad, &view.angle_down_rad};
    for (int i = 0; i < 4; ++i) *angles[i] = static_cast<float>((*o.fov.angles)[i] * kPi / 180.0);
  }
  if (o.pose) {
    for (int i = 0; i < 3; ++i) view.position_m[i] = static_cast<float>((*o.pose)[i]);
    for (int i = 0; i < 4; ++i) view.orientation_xyzw[i] = static_cast<float>((*o.pose)[3 + i]);
  }
  return view;
}

std::array<double, 4> fov_deg(const FoveartEyeView& view) {
  const auto deg = [](float rad) { return double(rad) * 180.0 / std::numbers::pi; };
  return {deg(view.angle_left_rad), deg(view.angle_right_rad), deg(view.angle_up_rad), deg(view.angle_down_rad)};
}

namespace {

std::string check_view(const RenderOptions& o) {
  if (std::string bad = fov_deg_problem(o.fov); !bad.empty()) return "--fov-deg: " + bad;
  if (o.pose) {
    double norm2 = 0.0;
    for (int i = 0; i < 7; ++i) {
      if (!std::isfinite((*o.pose)[i])) return "--pose values must be finite";
      if (i >= 3) norm2 += (*o.pose)[i] * (*o.pose)[i];
    }
    if (std::abs(norm2 - 1.0) > double(foveation::kUnitQuaternionTolerance))
      return "--pose: the quaternion qx,qy,qz,qw must have unit length";
    if (o.look_at_m) return "--look-at turns a standing viewer (--pose X,Y,Z), not an exact eye pose";
  }
  const std::optional<std::array<double, 3>> position_m =
      o.pose ? std::optional(std::array<double, 3>{(*o.pose)[0], (*o.pose)[1], (*o.pose)[2]}) : o.viewer_m;
  if (position_m && !foveation::traceable_position(
                        glm::vec3(float((*position_m)[0]), float((*position_m)[1]), float((*position_m)[2]))))
    return "--pose: the position must be finite and within " + toolkit::format_g(foveation::kMaxPositionM) +
           " m of the origin on each axis";
  if (o.viewer_m && o.look_at_m && *o.viewer_m == *o.look_at_m) return "--look-at must differ from --pose X,Y,Z";
  return "";
}

}  // namespace

std::optional<foveation::DisplayTransform> render_display(const RenderOptions& o, engine::Tracer& tracer,
                                                          const FoveartEyeView& view, foveation::Executor& executor,
                                                          std::string* error) {
  return render_display(o, &foveart_engine_trace_rays, &tracer, view, executor, error);
}

std::optional<foveation::DisplayTransform> render_display(const RenderOptions& o, FoveartTraceRaysFn trace,
                                                          void* user_data, const FoveartEyeView& view,
                                                          foveation::Executor& executor, std::string* error) {
  foveation::DisplayTransform d;
  d.tone_map = *foveation::parse_tone_map(o.tone_map);
  if (o.exposure != "auto") {
    d.exposure = *foveation::parse_exposure(o.exposure);  // checked by check_render_options
    return d;
  }
  const std::optional<engine::AutoExposure> a =
      engine::auto_exposure(trace, user_data, view, executor, error);
  if (!a) return std::nullopt;
  d.exposure = a->exposure;
  return d;
}

engine::TracerOptions render_tracer_options(const RenderOptions& o) {
  engine::TracerOptions t;
  if (!o.without.empty()) {
    std::string unused;
    const engine::Effects left_out = *engine::parse_effects(o.without, &unused);
    t.allowed = engine::Effects::from_bits(engine::Effects::all().bits() & ~left_out.bits());
  }
  return t;
}

namespace {

std::string render_options_problem(const RenderOptions& o) {
  if (o.mode != "full" && o.mode != "foveated" && o.mode != "both") return "--mode must be full, foveated or both";
  if (o.eye != "left" && o.eye != "right") return "--eye must be left or right";
  if (o.interpolation != "nearest" && o.interpolation != "msm" && o.interpolation != "rbf") {
    return "--interpolation must be nearest, msm or rbf, got '" + o.interpolation + "'";
  }
  if (!preset_geometry(o.preset)) return "--preset: unknown display preset '" + o.preset + "'";
  if (o.rays_per_point < 1 || o.rays_per_point > 1024) return "--rays-per-point must be in 1..1024";
  if (o.k < 0 || o.k > 20) return "--k must be in 1..20";
  if (!(o.density_scale > 0.0) || o.density_scale > 100.0) return "--density-scale must be in (0, 100]";
  if (!(o.content_contrast >= 0.0) || o.content_contrast > 1.0)
    return "--content-contrast must be in [0, 1] (0: off), got " + toolkit::format_g(o.content_contrast);
  if (o.content_rays && (!(*o.content_rays >= 0.0) || *o.content_rays > 1.0))
    return "--content-rays must be in [0, 1] (0: off), got " + toolkit::format_g(*o.content_rays);
  if (o.content_rays_doubling_deg && !foveation::valid_rays_doubling_ecc_deg(*o.content_rays_doubling_deg))
    return "--content-rays-doubling must be in [0, 90] degrees (0: off), got " +
           toolkit::format_g(*o.content_rays_doubling_deg);
  if (!o.pattern.empty() && !foveation::parse_fovea_pattern(o.pattern))
    return "--pattern must be pixel-grid or thesis, got '" + o.pattern + "'";
  if (o.threads < 0 || o.threads > int(foveation::kMaxExecutorThreads))
    return "--threads must be in 0.." + std::to_string(foveation::kMaxExecutorThreads) + " (0: all cores), got " +
           std::to_string(o.threads);
  if (o.frames < 1 || o.frames > 1000) return "--frames must be in 1..1000";
  if (o.gaze_px_per_frame.size() > std::size_t(o.frames))
    return "--gaze lists " + std::to_string(o.gaze_px_per_frame.size()) + " gazes, more than --frames " +
           std::to_string(o.frames);
  if (o.size_px && (o.size_px->x < 8 || o.size_px->y < 8 || o.size_px->x > 16384 || o.size_px->y > 16384))
    return "--size must be between 8x8 and 16384x16384 pixels";
  if (std::string bad = check_view(o); !bad.empty()) return bad;
  if (!o.without.empty()) {
    std::string bad;
    if (!engine::parse_effects(o.without, &bad)) return "--without: " + bad;
  }
  if (o.exposure != "auto" && !foveation::parse_exposure(o.exposure))
    return "--exposure must be auto or a number in (0, " + std::to_string(std::lround(foveation::kMaxExposure)) +
           "], got '" + o.exposure + "'";
  if (!foveation::parse_tone_map(o.tone_map))
    return "--tone-map must be none, pbr-neutral or aces, got '" + o.tone_map + "'";
  if (o.mode == "full" && o.temporal != foveation::TemporalMode::off) return "--temporal needs --mode foveated or both";
  return "";
}

}  // namespace

bool check_render_options(const RenderOptions& o, std::string* error) {
  std::string problem = render_options_problem(o);
  if (problem.empty()) return true;
  *error = std::move(problem);
  return false;
}

}  // namespace foveart::render_view
