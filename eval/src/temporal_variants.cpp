// The lab's temporal variants (temporal_variants.hpp).
#include <eval/temporal_variants.hpp>

#include <foveation/image_history.hpp>
#include <foveation/ray_history.hpp>

#include <algorithm>
#include <array>
#include <sstream>
#include <utility>

namespace foveart::eval {
namespace {

constexpr std::array<std::pair<TemporalVariant, const char*>, 5> kNames = {{
    {TemporalVariant::off, "off"},
    {TemporalVariant::restart, "restart"},
    {TemporalVariant::image, "image"},
    {TemporalVariant::rays, "rays"},
    {TemporalVariant::rays_kept, "rays-kept"},
}};

constexpr const char* kChoices = "off, restart, image, rays or rays-kept";

}  // namespace

const char* temporal_variant_name(TemporalVariant variant) {
  for (const auto& [v, name] : kNames)
    if (v == variant) return name;
  return "off";
}

bool parse_temporal_variant(std::string_view text, TemporalVariant* out) {
  for (const auto& [v, name] : kNames)
    if (text == name) {
      *out = v;
      return true;
    }
  return false;
}

bool parse_temporal_variants(const std::string& text, std::vector<TemporalVariant>* out, std::string* error) {
  out->clear();
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    TemporalVariant v{};
    if (!parse_temporal_variant(item, &v)) {
      *error = "--temporal: '" + item + "' is not " + kChoices;
      return false;
    }
    if (std::find(out->begin(), out->end(), v) != out->end()) {
      *error = "--temporal: '" + item + "' given twice";
      return false;
    }
    out->push_back(v);
  }
  if (out->empty() || text.back() == ',') {
    *error = std::string("--temporal: expected ") + kChoices + " or a list of them";
    return false;
  }
  return true;
}

foveation::TemporalMode product_mode(TemporalVariant variant) {
  switch (variant) {
    case TemporalVariant::off: return foveation::TemporalMode::off;
    case TemporalVariant::restart:
    case TemporalVariant::image: return foveation::TemporalMode::image;
    case TemporalVariant::rays:
    case TemporalVariant::rays_kept: return foveation::TemporalMode::rays;
  }
  return foveation::TemporalMode::off;
}

VariantSettings variant_settings(const render_view::RenderOptions& o, bool mean_while_young, float exposure) {
  VariantSettings s{o.rays_per_point, o.seed, o.pixel_filter, mean_while_young};
  s.content_density = render_view::foveated_view_settings(o).content_density;
  s.content_density.exposure = exposure;
  return s;
}

foveation::ViewSettings variant_view_settings(TemporalVariant variant, const VariantSettings& s) {
  foveation::ViewSettings vs = foveation::temporal_view_settings(product_mode(variant), s.rays_per_point, s.seed);
  vs.pixel_filter = s.pixel_filter;
  vs.temporal_options.mean_while_young = s.mean_while_young;
  vs.content_density = s.content_density;
  return vs;
}

std::unique_ptr<foveation::TemporalHistory> make_variant_history(TemporalVariant variant,
                                                                 const foveation::ViewTables& tables,
                                                                 const foveation::ViewSettings& vs) {
  switch (variant) {
    case TemporalVariant::restart:
      return std::make_unique<foveation::ImageHistory>(tables.neighbors, vs.blend_options(), /*reproject=*/false);
    case TemporalVariant::rays_kept:
      return std::make_unique<foveation::RayHistory>(
          tables, vs.blend_options(),
          foveation::RayHistoryOptions{vs.pixel_filter, vs.ray_cache_max_age_frames, /*keep_through_restarts=*/true});
    case TemporalVariant::off:
    case TemporalVariant::image:
    case TemporalVariant::rays:
      break;
  }
  return foveation::make_temporal_history(tables, vs);
}

std::unique_ptr<foveation::FoveatedView> make_variant_view(TemporalVariant variant,
                                                           std::shared_ptr<const foveation::ViewTables> tables,
                                                           const VariantSettings& settings) {
  const foveation::ViewSettings vs = variant_view_settings(variant, settings);
  std::unique_ptr<foveation::TemporalHistory> history = make_variant_history(variant, *tables, vs);
  return std::make_unique<foveation::FoveatedView>(std::move(tables), vs, std::move(history));
}

}  // namespace foveart::eval
