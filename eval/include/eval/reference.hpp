// The converged reference a rendered image is measured against: a full render
// with many jittered rays per pixel, its residual error estimated per
// eccentricity ring, cached on disk.
//
// Estimate (docs/pricelist.md "The reference"): the reference is the mean of
// two halves A and B, each spp/2 rays per pixel with independent jitter. Both
// are unbiased estimates of the pixel's true colour with the same variance s2,
// so E[(A - B)^2] = 2 s2 and the mean (A + B)/2 has variance s2 / 2 =
// E[(A - B)^2] / 4: the reference's own mean squared error against the truth is
// MSE(A, B) / 4, per ring (in display values, to first order in the noise).
// An image measured against it reads MSE(image, truth) + that residual.
//
// Cache: one file per (scene content, view, spp, seed, pixel filter, chunk size) in a
// directory, checksummed (XXH3-64); a corrupt or mismatched file is reported
// through `log` and rendered again. Errors (a failing engine, an unwritable
// cache) come back as messages; nothing throws.
#pragma once

#include <engine/scene.hpp>
#include <engine/tracer.hpp>

#include <foveation/executor.hpp>
#include <foveation/image.hpp>
#include <metrics/image_metrics.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/ray_trace.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace foveart::eval {

// The convergence check (spp = 0): a full render at s rays per pixel has MSE
// sigma^2 / s against the truth, the reference at N has sigma^2 / N, so the
// reference is margin_db below the best full render measured (baseline_spp)
// once N >= baseline_spp * 10^(margin_db / 10). The check doubles N from
// min_spp until then and until the estimated residual has fallen by at least
// 2 dB per doubling in every ring, on average since min_spp (the 1/N law gives
// 3; a slower fall would mean the halves are not independent or the renderer
// is biased, and the estimate could not be trusted; a faster one, seen at low
// counts where a few pixels' rare hits dominate, does not make the estimate at
// N wrong); max_spp caps it.
struct ReferenceOptions {
  int spp = 0;                 // rays per pixel in all (even); 0: chosen by the convergence check
  int min_spp = 32;            // the convergence check starts here and doubles
  int max_spp = 1024;          // ... up to here
  int baseline_spp = 16;       // the most rays per pixel of a full render it must be far below
  double margin_db = 10.0;
  std::uint64_t seed = 1;
  // The pixel filter of the reference's rays: the one of the images measured
  // against it, so that it is their expectation (ray_samples.hpp).
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  std::string cache_dir;       // empty: no cache
};

struct Reference {
  foveation::ImageRgb image;            // linear RGB, (A + B) / 2
  std::vector<float> half_difference2;  // per pixel: mean over channels of (enc(A) - enc(B))^2, display values
  std::vector<float> half_difference_luma;  // per pixel: Rec. 601 luma of enc(A) - enc(B), signed
  int spp = 0;
  bool from_cache = false;
  double render_ms = 0.0;               // this run's rendering (0 when loaded)
  std::string cache_file;               // empty without a cache
  std::vector<int> tried_spp;           // the convergence check's steps
  // Per ring: how much each doubling of the check lowered the residual on
  // average since min_spp (dB; 3 under the 1/N law). Empty without a check.
  std::vector<double> db_per_doubling;
  bool converged = true;                // false: the check stopped at max_spp short of its goal

  // Residual MSE per ring against the truth, MSE(A, B) / 4, and its PSNR.
  std::array<double, metrics::kRingCount> residual_mse(const metrics::EccentricityMap& map) const;
};

using ReferenceLog = std::function<void(const std::string&)>;

// XXH3-64 of everything in a scene that changes a pixel (mesh, materials,
// textures, lights, sky, ambient).
std::uint64_t scene_content_hash(const engine::Scene& scene);
// What a tracer renders of its scene: scene_content_hash, and the effects it
// leaves out (TracerOptions::allowed) when it leaves any out. With every
// effect the scene calls for it is scene_content_hash, so the caches of such
// renders keep their names.
std::uint64_t rendered_scene_hash(const engine::Tracer& tracer);

// Loads (or renders and stores) the reference of `view`. `gaze_px` picks the
// rings the convergence check looks at. nullopt with *error when the engine
// fails or the cache cannot be written.
std::optional<Reference> converged_reference(FoveartTraceRaysFn fn, void* user_data, std::uint64_t scene_hash,
                                             const FoveartEyeView& view, glm::vec2 gaze_px,
                                             const ReferenceOptions& options, foveation::Executor& executor,
                                             const ReferenceLog& log, std::string* error);

// The cache file of one reference (exposed for tests).
std::filesystem::path reference_cache_path(const std::string& cache_dir, std::uint64_t scene_hash,
                                           const FoveartEyeView& view, int spp, std::uint64_t seed,
                                           foveation::PixelFilter filter);
// Reads a cache file written by converged_reference; nullopt with *error (naming
// the file and what is wrong) when it is missing, truncated, corrupt or of another key.
std::optional<Reference> read_reference(const std::filesystem::path& file, std::uint64_t key, std::string* error);
std::string write_reference(const std::filesystem::path& file, std::uint64_t key, const Reference& reference);
std::uint64_t reference_key(std::uint64_t scene_hash, const FoveartEyeView& view, int spp, std::uint64_t seed,
                            foveation::PixelFilter filter);

}  // namespace foveart::eval
