// `fovea-eval pricelist`: what every setting costs in time and rays and buys in
// accuracy against a converged reference, per eccentricity ring
// (docs/lab/pricelist.md).
#pragma once

#include <array>

#include <eval/pricelist_grid.hpp>
#include <eval/pricelist_temporal.hpp>

#include <glm/ext/vector_int2.hpp>
#include <glm/vec2.hpp>

#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace foveart::eval {

void register_pricelist(CLI::App& app);

struct PricelistOptions {
  std::string scene = "default";
  std::string preset = "fove";
  std::string eye = "left";
  std::optional<glm::vec2> gaze_px;     // default: image centre
  std::optional<glm::ivec2> size_px;    // default: the preset's
  // A standing viewer (RenderOptions::viewer_m, look_at_m): --pose X,Y,Z, --look-at X,Y,Z.
  std::optional<std::array<double, 3>> viewer_m;
  std::optional<std::array<double, 3>> look_at_m;
  // The exposure the metrics see (RenderOptions::exposure): "auto" or a linear scale.
  std::string exposure = "auto";
  std::string out_dir;                  // required; re-running with it resumes
  std::string cache_dir;                // tables and reference; default OUT/cache
  std::string reference_spp = "auto";   // "auto" or an even count
  int frames = 3;                       // interleaved frames per setting; the median is reported
  int history_frames = 8;               // sequence length of a setting with the image history
  int threads = 0;                      // executor threads, 0 = all cores
  bool quick = false;
  PriceGrid grid;                       // replaced by quick_grid() when quick
  std::string heatmap;                  // setting id for the error heat map; default the thesis default
  bool images = false;                  // write every setting's image as PFM (display values)
  std::uint64_t seed = 1;
  // What every ray of a pixel follows, in every setting and every reference
  // (foveation/ray_samples.hpp).
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  TemporalOptions temporal;             // the temporal columns (motion "none": without them)
  // The perceptual metric's display (PerceptualDisplay): what display value 1.0 emits, cd/m^2.
  double white_cd_m2 = 100.0;
  std::string md_file;                  // also write report.md here, its links pointing into out_dir
  std::string command;                  // the command line report.md names; default the recorded one
};

int run_pricelist(const PricelistOptions& options, std::ostream& out, std::ostream& err);

}  // namespace foveart::eval
