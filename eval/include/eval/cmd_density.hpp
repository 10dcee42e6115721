// `fovea-eval density`: how few rays foveation may trace before the perceptual metric sees it.
// One still view (a crop of the preset's view at its pixels per degree, --crop, keeps it quick),
// one gaze: the full render at --rays-per-point rays per pixel (the baseline) and the foveated
// frame over eccentricity-only density (--scales, the thesis's density scale), content-aware
// density (--contrasts, at --density-scale), rays per point by contrast (--ray-contrasts, at
// --density-scale; foveation/point_rays.hpp) and both from one contrast (--both-contrasts), each
// (with --content-at-unseen, also at the sparsest eccentricity-only scale the metric does not see)
// against a converged reference through the
// metric (eval/density_detection.hpp) on the view's display (its exposure and tone map). Per row
// the ray fraction, the density's and the frame's ms and each ring's largest P; per kind the
// smallest ray fraction at which every ring stays below P = 0.5, among the rings where the full
// render itself stays below it (elsewhere its own noise hides foveation); and the content-aware row
// (any of its kinds) with the fewest rays at eccentricity-only's detection (detected_no_more). JSON on stdout;
// with --out PREFIX, every frame measured and P per pixel beside it as PNGs, to look at what the metric sees;
// with --ring-multiples, how many times above threshold each ring of each frame is.
#pragma once

#include <eval/lab_options.hpp>

#include <render_view/render_options.hpp>

#include <glm/ext/vector_int2.hpp>

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace foveart::eval {

struct DensityOptions {
  render_view::RenderOptions render;   // view, method, k, pattern, rays per point, cache, exposure
  std::optional<glm::ivec2> crop_px;   // a WxH crop of the preset's view at its pixels per degree
  ReferenceChoice reference;           // a count of rays per pixel is required
  std::vector<double> scales = {1.0, 1.5, 2.0, 3.0};
  std::vector<double> contrasts = {0.25, 0.5, 1.0};
  std::vector<double> ray_contrasts;  // none unless asked for: the benchmark's sweeps stay as they were
  std::vector<double> both_contrasts;  // rows that thin and vary the rays per point from the same contrast
  // Eccentricities over which the rays and both rows' contrast doubles (ContentDensityOptions::
  // rays_doubling_ecc_deg), a row each; empty: render.content_rays_doubling_deg alone.
  std::vector<double> rays_doublings;
  // The content-aware rows also at the sparsest eccentricity-only scale the metric does not see
  // (where it is not render.density_scale): thinning from a density nobody sees.
  bool content_at_unseen = false;
  bool ring_multiples = false;  // each row's (and the full render's) threshold multiple per ring
  double white_cd_m2 = 100.0;
};

void register_density(CLI::App& app);

// 0, 2 for bad options, 1 when the scene, the engine, the reference or the tables fail.
int run_density(const DensityOptions& options, std::ostream& out, std::ostream& err);

// Whether the metric sees nothing that foveation adds: every ring the full render at the same rays
// per pixel does not show (its largest P below 0.5; the measurable rings) stays below P = 0.5 at the
// row's most visible pixel. A ring the full render already shows cannot tell foveation from that
// render's own noise. Per ring the largest P of the row and of the full render; NaN: no pixels there.
bool unseen_in_every_ring(const std::vector<double>& row_p_max, const std::vector<double>& full_p_max);

// How many rings unseen_in_every_ring can judge: those where the full render's largest P is below 0.5.
// With none, every row is "unseen" for want of a ring to see it in, and says nothing.
std::size_t measurable_ring_count(const std::vector<double>& full_p_max);

// One row of a sweep: its primary rays over the full render's, and unseen_in_every_ring's verdict.
struct UnseenCandidate {
  double ray_fraction = 0.0;
  bool unseen = false;
};

// The smallest ray fraction the metric does not see: the index of the unseen row with the fewest
// rays (the first on a tie); nullopt when no row is unseen.
std::optional<std::size_t> smallest_unseen(const std::vector<UnseenCandidate>& rows);

// Whether a row is detected no more than a baseline row: in every ring, its largest P exceeds the
// baseline's by at most kSameDetectionP (a ring without pixels in either is skipped). What
// "content-aware density reaches the same detection probability as eccentricity-only" means.
inline constexpr double kSameDetectionP = 0.01;  // one percentage point: the tables' precision
bool detected_no_more(const std::vector<double>& row_p_max, const std::vector<double>& baseline_p_max);

}  // namespace foveart::eval
