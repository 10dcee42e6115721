// The price list's settings and their names.
#include <eval/pricelist_grid.hpp>

#include <toolkit/format.hpp>

#include <sstream>
#include <utility>

namespace foveart::eval {

std::string PriceSetting::id() const {
  if (full) return "full_spp" + std::to_string(rays_per_point) + (history ? "_image" : "");
  return table_id() + "_r" + std::to_string(rays_per_point) +
         (content_contrast > 0.0 ? "_c" + toolkit::format_g(content_contrast) : "") +
         (content_rays > 0.0 ? "_cr" + toolkit::format_g(content_rays) : "") +
         (history ? "_image" : "");  // e.g. nearest_k1_s1_thesis_r1, msm_k5_s1_pixel-grid_r1_c0.5
}

std::string PriceSetting::table_id() const {
  if (full) return "full";
  return interpolation + "_k" + std::to_string(k) + "_s" + toolkit::format_g(density_scale) + "_" + pattern;
}

PriceGrid quick_grid() {
  PriceGrid g;
  g.full_rays_per_point = {1, 2, 4, 8};  // the reference then needs 10 x 8 rays per pixel (128), not 10 x 16 (256)
  g.interpolation = {"nearest:1", "msm:5"};
  g.density_scale = {1.0, 2.0};
  g.rays_per_point = {1, 4};
  g.pattern = {"pixel-grid", "thesis"};
  g.history_rays_per_point = {1};
  g.content_contrast = {0.5};
  g.content_rays = {0.5};
  return g;
}

bool split_list(const std::string& text, std::vector<std::string>* out) {
  out->clear();
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) return false;
    out->push_back(item);
  }
  return !out->empty();
}

namespace {

// A foveated setting at each rays per point, without and with the image history.
std::string add_foveated_rows(const PriceGrid& g, PriceSetting s, std::vector<PriceSetting>* out) {
  for (int r : g.rays_per_point) {
    if (r < 1 || r > 1024) return "rays per point " + std::to_string(r) + " (1..1024)";
    s.rays_per_point = r;
    s.history = false;
    out->push_back(s);
  }
  for (int r : g.history_rays_per_point) {
    s.rays_per_point = r;
    s.history = true;
    out->push_back(s);
  }
  return "";
}

// The content-aware family of one foveated setting: each content contrast at each rays per point,
// then each contrast of rays per point by content at each rays per point above 1; no history.
std::string add_content_rows(const PriceGrid& g, PriceSetting s, std::vector<PriceSetting>* out) {
  s.history = false;
  for (double contrast : g.content_contrast) {
    if (!(contrast >= 0.0) || contrast > 1.0) return "content contrast " + toolkit::format_g(contrast) + " [0, 1]";
    if (contrast == 0.0) continue;  // the eccentricity-only rows
    s.content_contrast = contrast;
    for (int r : g.rays_per_point) {
      s.rays_per_point = r;
      out->push_back(s);
    }
  }
  s.content_contrast = 0.0;
  for (double contrast : g.content_rays) {
    if (!(contrast > 0.0) || contrast > 1.0) return "content rays " + toolkit::format_g(contrast) + " (0, 1]";
    s.content_rays = contrast;
    for (int r : g.rays_per_point) {
      if (r == 1) continue;
      s.rays_per_point = r;
      out->push_back(s);
    }
  }
  return "";
}

std::string grid_problem(const PriceGrid& g, std::vector<PriceSetting>* out) {
  out->clear();
  for (int spp : g.full_rays_per_point) {
    if (spp < 1 || spp > 1024) return "full-render rays per pixel " + std::to_string(spp) + " (1..1024)";
    PriceSetting s;
    s.full = true;
    s.rays_per_point = spp;
    out->push_back(s);
  }
  for (int r : g.history_rays_per_point) {  // the full render with the foveated rows' image history
    if (r < 1 || r > 1024) return "history rays per point " + std::to_string(r) + " (1..1024)";
    PriceSetting s;
    s.full = true;
    s.rays_per_point = r;
    s.history = true;
    out->push_back(s);
  }
  for (const std::string& pattern : g.pattern)
    if (pattern != "pixel-grid" && pattern != "thesis") return "pattern '" + pattern + "' (pixel-grid or thesis)";
  for (const std::string& mk : g.interpolation) {
    const auto colon = mk.find(':');
    const std::string method = mk.substr(0, colon);
    if (method != "nearest" && method != "msm" && method != "rbf")
      return "interpolation '" + mk + "' (nearest, msm or rbf)";
    int k = method == "nearest" ? 1 : 5;
    if (colon != std::string::npos) {
      try {
        std::size_t used = 0;
        k = std::stoi(mk.substr(colon + 1), &used);
        if (used != mk.size() - colon - 1) throw std::invalid_argument(mk);
      } catch (const std::exception&) {
        return "interpolation '" + mk + "': k is not a number";
      }
    }
    if (k < 1 || k > 20 || (method == "nearest" && k != 1)) {
      return "interpolation '" + mk + "': k must be 1 for nearest, 1..20 otherwise";
    }
    for (double scale : g.density_scale) {
      if (!(scale > 0.0) || scale > 100.0) return "density scale " + toolkit::format_g(scale) + " (0, 100]";
      for (const std::string& pattern : g.pattern) {
        PriceSetting s;
        s.interpolation = method;
        s.k = k;
        s.density_scale = scale;
        s.pattern = pattern;
        if (std::string bad = add_foveated_rows(g, s, out); !bad.empty()) return bad;
        if (std::string bad = add_content_rows(g, s, out); !bad.empty()) return bad;
      }
    }
  }
  return "";
}

}  // namespace

bool expand_grid(const PriceGrid& g, std::vector<PriceSetting>* out, std::string* error) {
  std::string problem = grid_problem(g, out);
  if (problem.empty()) return true;
  *error = std::move(problem);
  return false;
}

}  // namespace foveart::eval
