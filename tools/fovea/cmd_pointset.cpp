// fovea pointset: build (or load) the point set and neighbour table of a display,
// and report them: counts (thesis Table 1), a picture (Fig. 12), curves (Figs. 11, 14).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include <render_view/display_options.hpp>
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_density.hpp"
#include "foveation/point_set_cache.hpp"
#include "foveation/visible_points.hpp"
#include "toolkit/image_io.hpp"
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

glm::vec2 parse_gaze(const std::string& text, int w, int h) {
  if (text.empty()) return {0.5f * float(w), 0.5f * float(h)};
  const auto comma = text.find(',');
  if (comma == std::string::npos) throw CLI::ValidationError("--gaze", "expected X,Y in pixels, got '" + text + "'");
  try {
    std::size_t used_x = 0, used_y = 0;
    const std::string xs = text.substr(0, comma), ys = text.substr(comma + 1);
    const float x = std::stof(xs, &used_x);
    const float y = std::stof(ys, &used_y);
    if (used_x != xs.size() || used_y != ys.size()) throw std::invalid_argument("trailing characters");
    if (!std::isfinite(x) || !std::isfinite(y)) throw std::invalid_argument("not finite");
    return {x, y};
  } catch (const std::exception&) {
    throw CLI::ValidationError("--gaze", "expected two finite numbers X,Y, got '" + text + "'");
  }
}

// Fails early, before minutes of work, when an output cannot be written.
void check_output_file(const std::string& path, const char* option) {
  if (path.empty()) return;
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw CLI::ValidationError(option, "directory does not exist: " + dir.string());
  std::ofstream probe(p, std::ios::app);
  if (!probe) throw CLI::ValidationError(option, "cannot write " + path);
}

void check_output_dir(const std::string& path, const char* option) {
  if (path.empty()) return;
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec || !fs::is_directory(path)) throw CLI::ValidationError(option, "cannot create directory " + path);
  const fs::path probe_file = fs::path(path) / ".fovea_write_probe";
  std::ofstream probe(probe_file);
  if (!probe) throw CLI::ValidationError(option, "cannot write into " + path);
  probe.close();
  fs::remove(probe_file, ec);
}

// Thesis Fig. 12: every on-screen point as a dark pixel on white.
void write_points_png(const std::string& path, const fv::VisiblePoints& vis, int w, int h) {
  std::vector<std::uint8_t> px(std::size_t(w) * std::size_t(h), 255);
  for (const auto& s : vis.screen_px) {
    const int x = int(std::floor(s.x));
    const int y = int(std::floor(s.y));
    if (x >= 0 && y >= 0 && x < w && y < h) px[std::size_t(y) * std::size_t(w) + std::size_t(x)] = 0;
  }
  if (std::string err; !toolkit::write_png_u8(path, w, h, 1, px, &err)) throw std::runtime_error(err);
}

void write_or_throw(const std::string& err) {
  if (!err.empty()) throw std::runtime_error(err);
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
void write_density_curve(const std::string& dir, const fv::DisplayModel& display, const fv::PointSet& points) {
  const DensityCurve mine = density_curve(display, points);
  fv::DisplayModel other = display;
  other.fovea_pattern = display.fovea_pattern == fv::FoveaPattern::kPixelGrid ? fv::FoveaPattern::kThesisPoisson
                                                                              : fv::FoveaPattern::kPixelGrid;
  const DensityCurve theirs = density_curve(other, fv::generate_point_set(other, 1));
  std::ofstream csv(fs::path(dir) / "density_vs_eccentricity.csv");
  csv << "pattern,ecc_deg,points_per_px,spacing_px\n";
  auto rows = [&](const fv::DisplayModel& d, const DensityCurve& c) {
    for (std::size_t i = 0; i < c.ecc_deg.size(); ++i)
      csv << fv::fovea_pattern_name(d.fovea_pattern) << ',' << c.ecc_deg[i] << ',' << c.points_per_px[i] << ','
          << c.spacing_px[i] << '\n';
  };
  rows(display, mine);
  rows(other, theirs);
  if (!csv) throw std::runtime_error("cannot write " + (fs::path(dir) / "density_vs_eccentricity.csv").string());
  const std::string a(fv::fovea_pattern_name(display.fovea_pattern)), b(fv::fovea_pattern_name(other.fovea_pattern));
  // Reference lines first, the measured curves on top.
  std::vector<toolkit::PlotSeries> series{
      {"one point per pixel", {0.0, mine.ecc_deg.empty() ? 1.0 : mine.ecc_deg.back()}, {1.0, 1.0}}};
  if (const double ecc = fv::pixel_grid_ecc_deg(display.display_cpd(), display.csf); ecc > 0.0) {
    series.push_back({"f_c = f_d (eq. 2-3)", {ecc, ecc}, {0.0, 2.5}});
  }
  series.push_back({b, theirs.ecc_deg, theirs.points_per_px});
  series.push_back({a, mine.ecc_deg, mine.points_per_px});
  write_or_throw(toolkit::write_plot_png((fs::path(dir) / "density_vs_eccentricity.png").string(),
                                         {"Measured point density: " + a + " against " + b,
                                          "eccentricity (deg, scaled)", "points per pixel (2 px rings)"},
                                         series));
}

// Thesis Fig. 11 (cut-off and display frequency, spacing against eccentricity)
// and Fig. 14 (point count against scale 1.0-3.0).
nlohmann::json write_curves(const std::string& dir, const fv::DisplayModel& display, const fv::PointSet& points) {
  const std::size_t count_at_scale = points.size();
  const double max_d = std::hypot(double(display.width_px), double(display.height_px));
  std::vector<double> ecc, fc, fd, radius;
  std::ofstream csv(fs::path(dir) / "spacing_vs_eccentricity.csv");
  csv << "distance_px,ecc_deg,cutoff_cpd,display_cpd,radius_px\n";
  for (double d = 0.0; d <= max_d; d += max_d / 400.0) {
    ecc.push_back(display.ecc_deg(d));
    fc.push_back(display.cutoff_cpd(d));
    fd.push_back(display.display_cpd());
    radius.push_back(display.radius_px(d));
    csv << d << ',' << ecc.back() << ',' << fc.back() << ',' << fd.back() << ',' << radius.back() << '\n';
  }
  if (!csv) throw std::runtime_error("cannot write " + (fs::path(dir) / "spacing_vs_eccentricity.csv").string());
  std::vector<double> fc_clipped = fc;
  for (auto& f : fc_clipped) f = std::min(f, 2.5 * display.display_cpd());
  write_or_throw(toolkit::write_plot_png(
      (fs::path(dir) / "cutoff_vs_eccentricity.png").string(),
      {"Cut-off frequency (thesis eq. 2) and display Nyquist (eq. 3)", "eccentricity (deg, scaled)",
       "cycles per degree"},
      {{"f_c (eq. 2)", ecc, fc_clipped}, {"f_d (eq. 3)", ecc, fd}}));
  write_or_throw(toolkit::write_plot_png((fs::path(dir) / "spacing_vs_eccentricity.png").string(),
                                         {"Point radius p (eq. 4)", "eccentricity (deg, scaled)", "radius (px)"},
                                         {{"p (eq. 4)", ecc, radius}}));

  write_density_curve(dir, display, points);

  std::vector<double> scales, counts;
  std::ofstream csv14(fs::path(dir) / "points_vs_scale.csv");
  csv14 << "scale,points\n";
  toolkit::Progress progress("fovea pointset: points against scale");
  const int steps = 8;
  for (int i = 0; i <= steps; ++i) {
    fv::DisplayModel d = display;
    d.scale = 1.0 + 2.0 * i / steps;
    const std::size_t n = (i == 0 && display.scale == 1.0) ? count_at_scale : fv::generate_point_set(d, 1).size();
    scales.push_back(d.scale);
    counts.push_back(double(n));
    csv14 << d.scale << ',' << n << '\n';
    progress.update(double(i + 1) / double(steps + 1));
  }
  write_or_throw(toolkit::write_plot_png((fs::path(dir) / "points_vs_scale.png").string(),
                                         {"Points in the set against density scale (thesis Fig. 14)",
                                          "density scale", "points"},
                                         {{"points", scales, counts, true}, {"", scales, counts}}));
  nlohmann::json j;
  for (std::size_t i = 0; i < scales.size(); ++i) j.push_back({{"scale", scales[i]}, {"points", counts[i]}});
  return j;
}

void run_pointset(const PointsetOptions& o) {
  const fv::DisplayModel display = render_view::resolve_display(o.display);
  if (o.k < 1 || o.k > fv::kMaxNeighbors) {
    throw CLI::ValidationError("--k", "k must be in 1..20, got " + std::to_string(o.k));
  }
  const glm::vec2 gaze_req = parse_gaze(o.gaze, display.width_px, display.height_px);
  check_output_file(o.png, "--png");
  check_output_dir(o.curves_dir, "--curves");
  check_output_dir(o.cache_dir, "--cache-dir");

  fv::PointSetKey key{display, o.display.seed, o.k};
  std::optional<fs::path> cache;
  if (!o.cache_dir.empty()) cache = fs::path(o.cache_dir);
  fv::FoveationTables tables;
  {
    toolkit::Progress progress("fovea pointset: building point set and neighbour table");
    fv::Executor executor;  // all cores
    tables = fv::load_or_build_tables(cache, key, executor, [&](double f) { progress.update(f); },
                                      [](const std::string& msg) { std::cerr << "fovea pointset: " << msg << "\n"; });
  }
  const int w = display.width_px, h = display.height_px;
  const auto centred = fv::map_gaze(w, h, {0.5f * float(w), 0.5f * float(h)});
  const auto corner = fv::map_gaze(w, h, {float(w), float(h)});
  const auto at_gaze = fv::map_gaze(w, h, gaze_req);
  if (at_gaze.clamped) {
    std::cerr << "fovea pointset: gaze (" << gaze_req.x << ", " << gaze_req.y << ") is off-screen; clamped to ("
              << at_gaze.gaze_px.x << ", " << at_gaze.gaze_px.y << ")\n";
  }
  const auto vis_centred = fv::select_visible_points(tables.points, centred, 0.0f);
  const std::size_t n_centred = vis_centred.size();
  const std::size_t n_corner = fv::select_visible_points(tables.points, corner, 0.0f).size();
  const std::size_t n_corner_margin = fv::select_visible_points(tables.points, corner).size();
  const auto vis_gaze = fv::select_visible_points(tables.points, at_gaze);
  const double pixels = double(w) * double(h);

  nlohmann::json j;
  j["preset"] = display.name;
  j["width"] = w;
  j["height"] = h;
  j["fov_deg"] = display.horizontal_fov_deg();
  j["view_distance_px"] = display.view_distance_px;
  j["pixels_per_degree"] = display.view_distance_px * 3.141592653589793 / 180.0;
  j["density_scale"] = display.scale;
  j["disc_rule"] = o.display.disc_rule;
  j["pattern"] = fv::fovea_pattern_name(display.fovea_pattern);
  j["seed"] = o.display.seed;
  j["csf"] = {{"ct0", display.csf.ct0}, {"alpha", display.csf.alpha}, {"e2_deg", display.csf.e2_deg}};
  j["k"] = o.k;
  j["total"] = tables.points.size();
  j["on_screen_centred"] = n_centred;
  j["on_screen_corner"] = n_corner;
  j["visible_corner_with_margin"] = n_corner_margin;
  j["pixels"] = std::size_t(w) * std::size_t(h);
  j["fraction_centred"] = double(n_centred) / pixels;
  j["gaze"] = {at_gaze.gaze_px.x, at_gaze.gaze_px.y};
  j["gaze_clamped"] = at_gaze.clamped;
  j["visible_at_gaze"] = vis_gaze.size();
  j["visible_margin_px"] = tables.points.visible_margin_px;
  // Where the pixel grid samples the fovea, and how dense the set is anywhere.
  const fv::PointDensity density = fv::measure_point_density(tables.points, 8.0, 8.0);
  // Grid points are traced only on the screen, so the margin does not change these counts.
  auto grid_points_of = [&](const fv::VisiblePoints& vis) {
    std::size_t n = 0;
    for (std::uint32_t i : vis.point_index) n += tables.points.on_pixel_grid(i);
    return n;
  };
  const double grid_radius_px = display.pixel_grid_radius_px();
  j["pixel_grid"] = {
      {"radius_px", std::isfinite(grid_radius_px) ? nlohmann::json(grid_radius_px) : nlohmann::json("all")},
      {"radius_deg", std::isfinite(grid_radius_px) ? std::atan(grid_radius_px / display.view_distance_px) * 180.0 / 3.141592653589793
                                                   : 90.0},
      {"radius_ecc_deg_scaled", std::max(0.0, fv::pixel_grid_ecc_deg(display.display_cpd(), display.csf))},
      {"points", density.pixel_grid_points},
      {"on_screen_centred", grid_points_of(vis_centred)},
      {"on_screen_at_gaze", grid_points_of(vis_gaze)}};
  j["max_points_in_a_pixel"] = density.max_points_in_a_pixel;
  j["max_points_per_px"] = density.max_points_per_px;  // densest 8x8 block of the canvas
  j["generation_ms"] = tables.generation_ms;
  j["table_ms"] = tables.table_ms;
  j["table_bytes"] = tables.neighbors.bytes();
  j["points_from_cache"] = tables.points_from_cache;
  j["table_from_cache"] = tables.neighbors_from_cache;

  if (!o.png.empty()) write_points_png(o.png, vis_gaze, w, h);
  if (!o.curves_dir.empty()) j["points_vs_scale"] = write_curves(o.curves_dir, display, tables.points);

  if (o.json) {
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "points: " << j["total"] << " total, " << n_centred << " on screen at centred gaze ("
              << 100.0 * double(n_centred) / pixels << "% of " << w << "x" << h << "), " << n_corner
              << " at corner gaze\n"
              << "pattern: " << fv::fovea_pattern_name(display.fovea_pattern) << ", pixel grid "
              << density.pixel_grid_points << " points within " << j["pixel_grid"]["radius_px"] << " px ("
              << j["pixel_grid"]["radius_deg"] << " deg); at most " << density.max_points_in_a_pixel
              << " point(s) in a pixel, " << density.max_points_per_px << " per pixel in the densest 8x8 block\n"
              << "neighbour table: k=" << o.k << ", " << double(tables.neighbors.bytes()) / 1e6 << " MB\n"
              << "time: point set " << tables.generation_ms << " ms, table " << tables.table_ms << " ms\n";
  }
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
  cmd->callback([opts] { run_pointset(*opts); });
}

}  // namespace foveart::fovea
