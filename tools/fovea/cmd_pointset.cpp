// fovea pointset: build (or load) the point set and neighbour table of a display,
// and report them: counts (thesis Table 1), a picture (Fig. 12), curves (Figs. 11, 14).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include <render_view/display_options.hpp>
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_density.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/visible_points.hpp"
#include "toolkit/image_io.hpp"
#include "toolkit/outputs.hpp"
#include "toolkit/plot.hpp"
#include "toolkit/progress.hpp"

namespace foveart::fovea {
namespace {

namespace fs = std::filesystem;
namespace fv = foveation;

struct PointsetOptions {
  render_view::DisplayOptions display;
  int k = fv::kMaxNeighbors;
  std::string gaze;  // "X,Y"; empty: centre
  std::string cache_dir;
  bool json = false;
  std::string png;
  std::string curves_dir;
};

constexpr const char* kPointsetWho = "fovea pointset: ";

// "X,Y" in pixels, empty: the centre; false and *error quoting the text.
[[nodiscard]] bool parse_gaze(const std::string& text, int w, int h, glm::vec2* gaze, std::string* error) {
  if (text.empty()) {
    *gaze = {0.5f * float(w), 0.5f * float(h)};
    return true;
  }
  std::istringstream in(text);
  float x = 0.0f, y = 0.0f;
  char comma = 0;
  if (!(in >> x >> comma >> y) || comma != ',' || !(in >> std::ws).eof() || !std::isfinite(x) || !std::isfinite(y)) {
    *error = "--gaze: expected two finite numbers X,Y in pixels, got '" + text + "'";
    return false;
  }
  *gaze = {x, y};
  return true;
}

// An output checked before the work (toolkit/outputs.hpp), its option named in *error.
[[nodiscard]] bool check_output(const std::string& path, const char* option, bool folder, std::string* error) {
  if (path.empty()) return true;
  if (folder ? toolkit::check_writable_dir(path, error) : toolkit::check_writable_file(path, error)) return true;
  *error = std::string(option) + ": " + *error;
  return false;
}

// Thesis Fig. 12: every on-screen point as a dark pixel on white; false and *error naming the file.
[[nodiscard]] bool write_points_png(const std::string& path, const fv::VisiblePoints& vis, int w, int h,
                                    std::string* error) {
  std::vector<std::uint8_t> px(std::size_t(w) * std::size_t(h), 255);
  for (const auto& s : vis.screen_px) {
    const int x = int(std::floor(s.x));
    const int y = int(std::floor(s.y));
    if (x >= 0 && y >= 0 && x < w && y < h) px[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 0;
  }
  return toolkit::write_png_u8(path, w, h, 1, px, error);
}

// A plot written, or false and *error (write_plot_png's message names the file).
[[nodiscard]] bool plot(const fs::path& file, const toolkit::PlotSpec& spec,
                        const std::vector<toolkit::PlotSeries>& series, std::string* error) {
  *error = toolkit::write_plot_png(file.string(), spec, series);
  return error->empty();
}

// Points per pixel in rings around the centre of interest, against the ring's
// eccentricity (deg, scaled), out to the screen's corner.
struct DensityCurve {
  std::vector<double> ecc_deg, points_per_px, spacing_px;
};
DensityCurve density_curve(const fv::DisplayModel& display, const fv::PointSet& points) {
  const double max_d = std::hypot(double(display.width_px), double(display.height_px));
  const fv::PointDensity density = fv::measure_point_density(points, 2.0, max_d);
  DensityCurve c;
  for (const fv::DensityRing& r : density.rings) {
    if (r.area_px < 1.0 || r.points == 0) continue;
    c.ecc_deg.push_back(display.ecc_deg(0.5 * (r.from_px + r.to_px)));
    c.points_per_px.push_back(r.points_per_px());
    c.spacing_px.push_back(1.0 / std::sqrt(r.points_per_px()));  // side of the square each point owns
  }
  return c;
}

// The measured spacing curve of the set, and of the thesis's Poisson reading
// for the same display: where the pixel grid ends the density must not jump.
[[nodiscard]] bool write_density_curve(const std::string& dir, const fv::DisplayModel& display,
                                       const fv::PointSet& points, std::string* error) {
  const DensityCurve mine = density_curve(display, points);
  fv::DisplayModel other = display;
  other.fovea_pattern = display.fovea_pattern == fv::FoveaPattern::kPixelGrid ? fv::FoveaPattern::kThesisPoisson
                                                                              : fv::FoveaPattern::kPixelGrid;
  const DensityCurve theirs = density_curve(other, fv::generate_point_set(other, 1));
  const fs::path csv_file = fs::path(dir) / "density_vs_eccentricity.csv";
  std::ofstream csv(csv_file);
  csv << "pattern,ecc_deg,points_per_px,spacing_px\n";
  auto rows = [&](const fv::DisplayModel& d, const DensityCurve& c) {
    for (std::size_t i = 0; i < c.ecc_deg.size(); ++i)
      csv << fv::fovea_pattern_name(d.fovea_pattern) << ',' << c.ecc_deg[i] << ',' << c.points_per_px[i] << ','
          << c.spacing_px[i] << '\n';
  };
  rows(display, mine);
  rows(other, theirs);
  if (!csv) {
    *error = "cannot write " + csv_file.string();
    return false;
  }
  const std::string a(fv::fovea_pattern_name(display.fovea_pattern)), b(fv::fovea_pattern_name(other.fovea_pattern));
  // Reference lines first, the measured curves on top.
  std::vector<toolkit::PlotSeries> series{
      {"one point per pixel", {0.0, mine.ecc_deg.empty() ? 1.0 : mine.ecc_deg.back()}, {1.0, 1.0}}};
  if (const double ecc = fv::pixel_grid_ecc_deg(display.display_cpd(), display.csf); ecc > 0.0) {
    series.push_back({"f_c = f_d (eq. 2-3)", {ecc, ecc}, {0.0, 2.5}});
  }
  series.push_back({b, theirs.ecc_deg, theirs.points_per_px});
  series.push_back({a, mine.ecc_deg, mine.points_per_px});
  return plot(fs::path(dir) / "density_vs_eccentricity.png",
              {"Measured point density: " + a + " against " + b, "eccentricity (deg, scaled)",
               "points per pixel (2 px rings)"},
              series, error);
}

// Thesis Fig. 11: cut-off and display frequency, and point radius, against eccentricity.
[[nodiscard]] bool write_spacing_curves(const std::string& dir, const fv::DisplayModel& display, std::string* error) {
  const double max_d = std::hypot(double(display.width_px), double(display.height_px));
  std::vector<double> ecc, fc, fd, radius;
  const fs::path csv_file = fs::path(dir) / "spacing_vs_eccentricity.csv";
  std::ofstream csv(csv_file);
  csv << "distance_px,ecc_deg,cutoff_cpd,display_cpd,radius_px\n";
  for (double d = 0.0; d <= max_d; d += max_d / 400.0) {
    ecc.push_back(display.ecc_deg(d));
    fc.push_back(display.cutoff_cpd(d));
    fd.push_back(display.display_cpd());
    radius.push_back(display.radius_px(d));
    csv << d << ',' << ecc.back() << ',' << fc.back() << ',' << fd.back() << ',' << radius.back() << '\n';
  }
  if (!csv) {
    *error = "cannot write " + csv_file.string();
    return false;
  }
  std::vector<double> fc_clipped = fc;
  for (auto& f : fc_clipped) f = std::min(f, 2.5 * display.display_cpd());
  const std::vector<toolkit::PlotSeries> frequencies{{"f_c (eq. 2)", ecc, fc_clipped}, {"f_d (eq. 3)", ecc, fd}};
  if (!plot(fs::path(dir) / "cutoff_vs_eccentricity.png",
            {"Cut-off frequency (thesis eq. 2) and display Nyquist (eq. 3)", "eccentricity (deg, scaled)",
             "cycles per degree"},
            frequencies, error))
    return false;
  const std::vector<toolkit::PlotSeries> radii{{"p (eq. 4)", ecc, radius}};
  return plot(fs::path(dir) / "spacing_vs_eccentricity.png",
              {"Point radius p (eq. 4)", "eccentricity (deg, scaled)", "radius (px)"}, radii, error);
}

// Thesis Fig. 14: point count against scale 1.0-3.0, into *points_vs_scale too.
[[nodiscard]] bool write_scale_curve(const std::string& dir, const fv::DisplayModel& display,
                                     std::size_t count_at_scale, nlohmann::json* points_vs_scale, std::string* error) {
  std::vector<double> scales, counts;
  const fs::path csv_file = fs::path(dir) / "points_vs_scale.csv";
  std::ofstream csv(csv_file);
  csv << "scale,points\n";
  toolkit::Progress progress("fovea pointset: points against scale");
  const int steps = 8;
  for (int i = 0; i <= steps; ++i) {
    fv::DisplayModel d = display;
    d.scale = 1.0 + 2.0 * i / steps;
    const std::size_t n = (i == 0 && display.scale == 1.0) ? count_at_scale : fv::generate_point_set(d, 1).size();
    scales.push_back(d.scale);
    counts.push_back(double(n));
    csv << d.scale << ',' << n << '\n';
    progress.update(double(i + 1) / double(steps + 1));
  }
  if (!csv) {
    *error = "cannot write " + csv_file.string();
    return false;
  }
  for (std::size_t i = 0; i < scales.size(); ++i)
    points_vs_scale->push_back({{"scale", scales[i]}, {"points", counts[i]}});
  const std::vector<toolkit::PlotSeries> series{{"points", scales, counts, true}, {"", scales, counts}};
  return plot(fs::path(dir) / "points_vs_scale.png",
              {"Points in the set against density scale (thesis Fig. 14)", "density scale", "points"}, series, error);
}

// --curves DIR: thesis Figs. 11 and 14 and the measured density; false and *error naming the file.
[[nodiscard]] bool write_curves(const std::string& dir, const fv::DisplayModel& display, const fv::PointSet& points,
                  nlohmann::json* points_vs_scale, std::string* error) {
  return write_spacing_curves(dir, display, error) && write_density_curve(dir, display, points, error) &&
         write_scale_curve(dir, display, points.size(), points_vs_scale, error);
}

// The options checked and the outputs probed before minutes of work: the display, or nullopt and *error.
std::optional<fv::DisplayModel> checked_display(const PointsetOptions& o, glm::vec2* gaze, std::string* error) {
  std::optional<fv::DisplayModel> display = render_view::resolve_display(o.display, error);
  if (!display) return std::nullopt;
  if (o.k < 1 || o.k > fv::kMaxNeighbors) {
    *error = "--k: k must be in 1.." + std::to_string(fv::kMaxNeighbors) + ", got " + std::to_string(o.k);
    return std::nullopt;
  }
  if (!parse_gaze(o.gaze, display->width_px, display->height_px, gaze, error) ||
      !check_output(o.png, "--png", false, error) || !check_output(o.curves_dir, "--curves", true, error) ||
      !check_output(o.cache_dir, "--cache-dir", true, error))
    return std::nullopt;
  return display;
}

// The point set and its neighbour table, from the cache or built (and stored).
fv::FoveationTables build_tables(const PointsetOptions& o, const fv::DisplayModel& display, std::ostream& err) {
  fv::PointSetKey key{display, o.display.seed, o.k};
  std::optional<fs::path> cache;
  if (!o.cache_dir.empty()) cache = fs::path(o.cache_dir);
  toolkit::Progress progress("fovea pointset: building point set and neighbour table");
  fv::Executor executor;  // all cores
  return fv::load_or_build_tables(cache, key, executor, [&](double f) { progress.update(f); },
                                  [&](const std::string& msg) { err << kPointsetWho << msg << "\n"; });
}

// The points on screen at a centred gaze, at the corner (with and without the margin) and at the gaze asked for.
struct Visible {
  fv::GazeMapping at_gaze;
  fv::VisiblePoints centred, gaze;
  std::size_t corner = 0, corner_with_margin = 0;
};

Visible visible_points(const fv::FoveationTables& tables, const fv::DisplayModel& display, glm::vec2 gaze) {
  const int w = display.width_px, h = display.height_px;
  const auto corner = fv::map_gaze(w, h, {float(w), float(h)});
  Visible v;
  v.at_gaze = fv::map_gaze(w, h, gaze);
  v.centred = fv::select_visible_points(tables.points, fv::map_gaze(w, h, {0.5f * float(w), 0.5f * float(h)}), 0.0f);
  v.corner = fv::select_visible_points(tables.points, corner, 0.0f).size();
  v.corner_with_margin = fv::select_visible_points(tables.points, corner).size();
  v.gaze = fv::select_visible_points(tables.points, v.at_gaze);
  return v;
}

nlohmann::json display_json(const PointsetOptions& o, const fv::DisplayModel& display) {
  nlohmann::json j;
  j["preset"] = display.name;
  j["width"] = display.width_px;
  j["height"] = display.height_px;
  j["fov_deg"] = display.horizontal_fov_deg();
  j["view_distance_px"] = display.view_distance_px;
  j["pixels_per_degree"] = display.view_distance_px * 3.141592653589793 / 180.0;
  j["density_scale"] = display.scale;
  j["disc_rule"] = o.display.disc_rule;
  j["pattern"] = fv::fovea_pattern_name(display.fovea_pattern);
  j["seed"] = o.display.seed;
  j["csf"] = {{"ct0", display.csf.ct0}, {"alpha", display.csf.alpha}, {"e2_deg", display.csf.e2_deg}};
  j["k"] = o.k;
  return j;
}

// Where the pixel grid samples the fovea, and how dense the set is anywhere.
void add_density_json(const fv::FoveationTables& tables, const fv::DisplayModel& display, const Visible& v,
                      nlohmann::json& j) {
  const fv::PointDensity density = fv::measure_point_density(tables.points, 8.0, 8.0);
  // Grid points are traced only on the screen, so the margin does not change these counts.
  auto grid_points_of = [&](const fv::VisiblePoints& vis) {
    std::size_t n = 0;
    for (std::uint32_t i : vis.point_index) n += tables.points.on_pixel_grid(i);
    return n;
  };
  auto radius_json = [](double radius_px) { return std::isfinite(radius_px) ? nlohmann::json(radius_px) : "all"; };
  auto radius_deg = [&](double radius_px) {
    return std::isfinite(radius_px) ? fv::eccentricity_deg(radius_px, display.view_distance_px) : 90.0;
  };
  const double grid_radius_px = display.pixel_grid_radius_px();
  const double exact_radius_px = display.exact_fovea_radius_px();
  std::size_t exact_points = 0;
  for (std::size_t i = 0; i < tables.points.size(); ++i) exact_points += tables.points.in_exact_fovea(i);
  j["pixel_grid"] = {
      {"radius_px", radius_json(grid_radius_px)},
      {"radius_deg", radius_deg(grid_radius_px)},
      {"radius_ecc_deg_scaled", std::max(0.0, fv::pixel_grid_ecc_deg(display.display_cpd(), display.csf))},
      {"points", density.pixel_grid_points},
      {"on_screen_centred", grid_points_of(v.centred)},
      {"on_screen_at_gaze", grid_points_of(v.gaze)},
      // The pixel-exact fovea: the grid of scale 1 (all of it at scale 1 and above).
      {"exact_fovea",
       {{"radius_px", radius_json(exact_radius_px)},
        {"radius_deg", radius_deg(exact_radius_px)},
        {"points", exact_points}}}};
  j["max_points_in_a_pixel"] = density.max_points_in_a_pixel;
  j["max_points_per_px"] = density.max_points_per_px;  // densest 8x8 block of the canvas
}

nlohmann::json report_json(const PointsetOptions& o, const fv::DisplayModel& display,
                           const fv::FoveationTables& tables, const Visible& v) {
  const double pixels = double(display.width_px) * double(display.height_px);
  nlohmann::json j = display_json(o, display);
  j["total"] = tables.points.size();
  j["on_screen_centred"] = v.centred.size();
  j["on_screen_corner"] = v.corner;
  j["visible_corner_with_margin"] = v.corner_with_margin;
  j["pixels"] = std::size_t(display.width_px) * std::size_t(display.height_px);
  j["fraction_centred"] = double(v.centred.size()) / pixels;
  j["gaze"] = {v.at_gaze.gaze_px.x, v.at_gaze.gaze_px.y};
  j["gaze_clamped"] = v.at_gaze.clamped;
  j["visible_at_gaze"] = v.gaze.size();
  j["visible_margin_px"] = tables.points.visible_margin_px;
  add_density_json(tables, display, v, j);
  j["generation_ms"] = tables.generation_ms;
  j["table_ms"] = tables.table_ms;
  j["table_bytes"] = tables.neighbors.bytes();
  j["points_from_cache"] = tables.points_from_cache;
  j["table_from_cache"] = tables.neighbors_from_cache;
  return j;
}

void print_text(const nlohmann::json& j, std::ostream& out) {
  const double pixels = j["pixels"].get<double>();
  const double centred = j["on_screen_centred"].get<double>();
  out << "points: " << j["total"] << " total, " << j["on_screen_centred"] << " on screen at centred gaze ("
      << 100.0 * centred / pixels << "% of " << j["width"] << "x" << j["height"] << "), " << j["on_screen_corner"]
      << " at corner gaze\n"
      << "pattern: " << j["pattern"].get<std::string>() << ", pixel grid " << j["pixel_grid"]["points"]
      << " points within " << j["pixel_grid"]["radius_px"] << " px (" << j["pixel_grid"]["radius_deg"] << " deg), "
      << j["pixel_grid"]["exact_fovea"]["points"] << " of them the pixel-exact fovea within "
      << j["pixel_grid"]["exact_fovea"]["radius_px"] << " px; at most " << j["max_points_in_a_pixel"]
      << " point(s) in a pixel, " << j["max_points_per_px"] << " per pixel in the densest 8x8 block\n"
      << "neighbour table: k=" << j["k"] << ", " << j["table_bytes"].get<double>() / 1e6 << " MB\n"
      << "time: point set " << j["generation_ms"] << " ms, table " << j["table_ms"] << " ms\n";
}

int run_pointset(const PointsetOptions& o, std::ostream& out, std::ostream& err) {
  glm::vec2 gaze{};
  std::string error;
  const std::optional<fv::DisplayModel> display = checked_display(o, &gaze, &error);
  if (!display) {
    err << kPointsetWho << error << "\n";
    return 2;
  }
  fv::FoveationTables tables;
  try {
    tables = build_tables(o, *display, err);
  } catch (const std::exception& e) {  // the cache or the build: what failed, named by the library
    err << kPointsetWho << e.what() << "\n";
    return 1;
  }
  const Visible v = visible_points(tables, *display, gaze);
  if (v.at_gaze.clamped) {
    err << kPointsetWho << "gaze (" << gaze.x << ", " << gaze.y << ") is off-screen; clamped to ("
        << v.at_gaze.gaze_px.x << ", " << v.at_gaze.gaze_px.y << ")\n";
  }
  nlohmann::json j = report_json(o, *display, tables, v);
  if ((!o.png.empty() && !write_points_png(o.png, v.gaze, display->width_px, display->height_px, &error)) ||
      (!o.curves_dir.empty() && !write_curves(o.curves_dir, *display, tables.points, &j["points_vs_scale"], &error))) {
    err << kPointsetWho << error << "\n";
    return 1;
  }
  if (o.json)
    out << j.dump(2) << "\n";
  else
    print_text(j, out);
  return 0;
}

}  // namespace

void register_pointset(CLI::App& app) {
  auto opts = std::make_shared<PointsetOptions>();
  CLI::App* cmd = app.add_subcommand("pointset", "build or load a display's point set and neighbour table");
  render_view::add_display_options(cmd, opts->display);
  cmd->add_option("--k", opts->k, "neighbours per canvas pixel (1-20)")->capture_default_str();
  cmd->add_option("--gaze", opts->gaze, "gaze X,Y in pixels for --png (default: centre)");
  cmd->add_option("--cache-dir", opts->cache_dir, "cache directory (load if valid, else build and store)");
  cmd->add_flag("--json", opts->json, "print one JSON object");
  cmd->add_option("--png", opts->png, "draw the on-screen points at the gaze (thesis Fig. 12)");
  cmd->add_option("--curves", opts->curves_dir, "write CSV + PNG curves (thesis Figs. 11, 14) into this folder");
  cmd->callback([opts] {
    const int code = run_pointset(*opts, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::fovea
