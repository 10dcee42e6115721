#include <render_view/render_cli.hpp>

#include <render_view/display_options.hpp>

#include <foveation/content_density.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace foveart::render_view {
namespace {

// "X,Y" -> two numbers.
template <typename Vec>
std::string parse_pair(const std::string& text, Vec* out) {
  std::istringstream in(text);
  char comma = 0;
  typename Vec::value_type a{}, b{};
  if (!(in >> a >> comma >> b) || comma != ',' || !(in >> std::ws).eof()) return "expected two numbers X,Y";
  *out = Vec(a, b);
  return "";
}

// "A,B,C,..." -> exactly N finite numbers.
template <std::size_t N>
std::string parse_list(const std::string& text, std::array<double, N>* out) {
  std::istringstream in(text);
  for (std::size_t i = 0; i < N; ++i) {
    char comma = ',';
    if ((i > 0 && !(in >> comma)) || comma != ',' || !(in >> (*out)[i]))
      return "expected " + std::to_string(N) + " comma-separated numbers";
    if (!std::isfinite((*out)[i])) return "values must be finite";
  }
  if (!(in >> std::ws).eof()) return "expected " + std::to_string(N) + " comma-separated numbers";
  return "";
}

// A content option's default in its help: the lab's value, or where it is left unset (`fovea
// render`), the product's default and when it applies.
std::string default_help(const std::optional<double>& value, double product_default, const char* applies) {
  std::ostringstream text;
  if (value)
    text << "default " << *value;
  else
    text << "default " << product_default << " " << applies;
  return text.str();
}

}  // namespace

glm::vec2 parse_gaze_option(const std::string& option, const std::string& text) {
  glm::vec2 g;
  if (std::string e = parse_pair(text, &g); !e.empty()) throw CLI::ValidationError(option, e);
  if (!std::isfinite(g.x) || !std::isfinite(g.y)) throw CLI::ValidationError(option, "must be finite");
  return g;
}

std::array<double, 3> parse_point_option(const std::string& option, const std::string& text) {
  std::array<double, 3> p{};
  if (std::string e = parse_list(text, &p); !e.empty()) throw CLI::ValidationError(option, e);
  return p;
}

void parse_pose_option(const std::string& option, const std::string& text, RenderOptions* out) {
  if (std::count(text.begin(), text.end(), ',') == 2) {
    std::array<double, 3> p{};
    if (std::string e = parse_list(text, &p); !e.empty()) throw CLI::ValidationError(option, e);
    out->viewer_m = p;
    return;
  }
  std::array<double, 7> p{};
  if (std::string e = parse_list(text, &p); !e.empty())
    throw CLI::ValidationError(option, "expected X,Y,Z (a standing viewer) or px,py,pz,qx,qy,qz,qw (an eye pose)");
  out->pose = p;
}

std::function<void()> add_render_options(CLI::App* cmd, const std::shared_ptr<RenderOptions>& opts) {
  auto size = std::make_shared<std::string>();
  auto fov = std::make_shared<std::string>();
  cmd->add_option("--scene", opts->scene, "glTF/GLB file, or 'default' for the built-in scene")->capture_default_str();
  cmd->add_option("--preset", opts->preset, "Display preset")->capture_default_str();
  cmd->add_option("--eye", opts->eye, "left or right")->capture_default_str();
  cmd->add_option("--mode", opts->mode, "full, foveated or both")->capture_default_str();
  cmd->add_option("--rays-per-point", opts->rays_per_point, "Rays per point (a full render's points are its pixels)")
      ->capture_default_str();
  cmd->add_option("--interpolation", opts->interpolation, "nearest, msm or rbf")->capture_default_str();
  cmd->add_option("--k", opts->k, "Neighbours per pixel (msm, rbf; default 5; nearest uses 1)");
  cmd->add_option("--density-scale", opts->density_scale, "Point density scale (thesis 4.1)")->capture_default_str();
  cmd->add_option("--content-contrast", opts->content_contrast,
                  "Content-aware density: a screen tile traces all its points from this Michelson contrast "
                  "(last frame's), about half from half of it, a quarter from a quarter, a ninth below; 0: off")
      ->capture_default_str();
  cmd->add_option("--content-rays", opts->content_rays,
                  "Rays per point by the content: a point casts all --rays-per-point rays from this Michelson "
                  "contrast of its tile (last frame's), (contrast / this)^2 of them below, and fewer where its disc "
                  "is under a pixel in radius; the pixel-exact fovea keeps all; 0: off; " +
                      default_help(opts->content_rays, foveation::kDefaultRaysContrast,
                                   "with several rays per point at --density-scale 1 or above, else off"));
  cmd->add_option("--content-rays-doubling", opts->content_rays_doubling_deg,
                  "Degrees of eccentricity over which --content-rays doubles, in steps: points from 1, 2, 3, 4 times "
                  "this away from the gaze cast all their rays from 2, 4, 8, 16 times that contrast; 0: off; " +
                      default_help(opts->content_rays_doubling_deg, foveation::kDefaultRaysDoublingEccDeg,
                                   "with --temporal rays, else off"));
  cmd->add_option("--pattern", opts->pattern,
                  "Fovea sampling: pixel-grid (default) or thesis (Poisson everywhere; the thesis preset's)");
  cmd->add_option("--frames", opts->frames,
                  "Frames per mode, modes interleaved; times are each mode's median frame (fovea-eval motion: the "
                  "sequence's frames)")
      ->capture_default_str();
  cmd->add_option("--threads", opts->threads, "Tracing threads (0 = all cores)")->capture_default_str();
  cmd->add_option("--size", *size, "Per-eye size WxH in pixels instead of the preset's (its horizontal FOV kept)");
  cmd->add_option("--fov-deg", *fov,
                  "Field of view in degrees: H, the horizontal span of a symmetric frustum, or an exact OpenXR "
                  "frustum L,R,U,D (XrFovf angles); the point set follows the horizontal span");
  add_renamed_option(cmd, "--fov", "--fov-deg L,R,U,D");
  cmd->add_option("--out", opts->out_prefix,
                  "Write PREFIX_full.png / PREFIX_foveated.png, and PREFIX_rays.png: the rays each point cast "
                  "(grey: filled from its parents)");
  cmd->add_option("--cache-dir", opts->cache_dir, "Directory for cached point sets and neighbour tables");
  cmd->add_option("--seed", opts->seed, "Seed of point set and jitter")->capture_default_str();
  cmd->add_option("--without", opts->without,
                  "Leave these effects out of the scene, the reference too: shadows, reflection, refraction, "
                  "textures, comma-separated (default: every effect the scene calls for)");
  add_pixel_filter_option(cmd, &opts->pixel_filter);
  cmd->add_flag("--json", opts->json, "Print the report as JSON");
  cmd->add_option("--exposure", opts->exposure,
                  "Linear exposure of the images written, or auto (a low-resolution pre-pass of the view)")
      ->capture_default_str();
  cmd->add_option("--tone-map", opts->tone_map, "Tone-mapping curve of the images written: none, pbr-neutral or aces")
      ->capture_default_str();
  auto look_at = std::make_shared<std::string>();
  cmd->add_option("--look-at", *look_at, "Turn the viewer to face this point X,Y,Z (metres, scene space)");
  return [opts, size, fov, look_at] {
    if (!look_at->empty()) opts->look_at_m = parse_point_option("--look-at", *look_at);
    if (!size->empty()) {
      glm::ivec2 s;
      if (std::string e; !parse_size(*size, &s, &e)) throw CLI::ValidationError("--size", e);
      opts->size_px = s;
    }
    if (!fov->empty()) {
      if (std::string e; !parse_fov_deg(*fov, &opts->fov, &e)) throw CLI::ValidationError("--fov-deg", e);
    }
  };
}

void add_temporal_option(CLI::App* cmd, const std::shared_ptr<RenderOptions>& opts) {
  auto temporal = std::make_shared<std::string>("off");
  CLI::Option* option =
      cmd->add_option("--temporal", *temporal,
                      "What the foveated frames keep from earlier ones, as the layer's \"temporal\": off, image (an "
                      "image history, reprojected with the head) or rays (a render cache of the traced rays; implies "
                      "--pixel-filter bspline2 unless given)")
          ->check(CLI::IsMember({"off", "image", "rays"}))
          ->capture_default_str();
  cmd->parse_complete_callback([opts, temporal, option, cmd] {
    if (option->count() == 0) return;
    foveation::TemporalMode mode{};
    foveation::parse_temporal_mode(*temporal, &mode);
    opts->temporal = mode;
    if (mode == foveation::TemporalMode::rays && cmd->get_option("--pixel-filter")->count() == 0)
      opts->pixel_filter = foveation::PixelFilter::bspline2;
  });
}

}  // namespace foveart::render_view
