// The lab's temporal variants (fovea-eval --temporal): the product's temporal
// modes (foveation::TemporalMode: off, image, rays) and the lab's variations
// built on them, each the TemporalHistory a FoveatedView takes from its caller.
// The product's `fovea render --temporal` takes the product's three only.
#pragma once

#include <foveation/foveated_view.hpp>
#include <foveation/ray_samples.hpp>
#include <foveation/temporal_mode.hpp>
#include <foveation/view_settings.hpp>
#include <foveation/view_tables.hpp>
#include <render_view/render_options.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace foveart::eval {

enum class TemporalVariant : std::uint8_t {
  off,        // the product's off: every frame from its own rays
  restart,    // an image history without reprojection: any new pose or frustum restarts it
  image,      // the product's image: an image history reprojected with the head
  rays,       // the product's rays: a render cache of the traced rays
  rays_kept,  // the render cache, its rays kept through saccades, blinks and gaze jumps
};

// "off" | "restart" | "image" | "rays" | "rays-kept".
const char* temporal_variant_name(TemporalVariant variant);
// False (and *out unchanged) for any other text.
[[nodiscard]] bool parse_temporal_variant(std::string_view text, TemporalVariant* out);
// "off,image,rays" -> the variants in order; false and *error naming the bad or repeated entry.
[[nodiscard]] bool parse_temporal_variants(const std::string& text, std::vector<TemporalVariant>* out,
                                           std::string* error);
// The product's mode a variant is built on (restart: image; rays-kept: rays).
foveation::TemporalMode product_mode(TemporalVariant variant);

// What every variant of a comparison shares: equal rays, one seed, one pixel
// filter (the lab measures every filter under every variant), and the blend of
// a young history (TemporalOptions::mean_while_young, --temporal-mean-while-young).
struct VariantSettings {
  int rays_per_point = 1;
  std::uint64_t seed = 1;
  foveation::PixelFilter pixel_filter = foveation::PixelFilter::box;
  bool mean_while_young = false;
  // Density that follows the content, as the product's view applies it (off by default).
  foveation::ContentDensityOptions content_density{};
};

// The shared settings of `o` (a foveated command's options), with the content density of
// `o` at the view's display exposure (radiance to display-linear), as `fovea render` applies it.
VariantSettings variant_settings(const render_view::RenderOptions& o, bool mean_while_young, float exposure);

// The view settings of a variant: its product mode's (foveation::temporal_view_settings:
// off keeps one jitter seed, the thesis's choice; a history draws new jitter each frame,
// which it accumulates) with the shared settings.
foveation::ViewSettings variant_view_settings(TemporalVariant variant, const VariantSettings& settings);

// The history of a variant for a view over `tables` with these view settings (`tables`
// must outlive it): the product's (foveation::make_temporal_history) or the lab's variation.
std::unique_ptr<foveation::TemporalHistory> make_variant_history(TemporalVariant variant,
                                                                 const foveation::ViewTables& tables,
                                                                 const foveation::ViewSettings& view_settings);

// The foveated view of a variant over `tables`.
std::unique_ptr<foveation::FoveatedView> make_variant_view(TemporalVariant variant,
                                                           std::shared_ptr<const foveation::ViewTables> tables,
                                                           const VariantSettings& settings);

}  // namespace foveart::eval
