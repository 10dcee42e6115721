// `fovea-eval perceptual` (cmd_perceptual.hpp).
#include <eval/cmd_perceptual.hpp>

#include <eval/detection_png.hpp>
#include <eval/perceptual_metric.hpp>
#include <eval/pfm.hpp>
#include <eval/pricelist_report.hpp>
#include <render_view/render_cli.hpp>

#include <foveation/executor.hpp>
#include <metrics/image_metrics.hpp>
#include <toolkit/image_io.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>

namespace foveart::eval {
namespace {

constexpr const char* kWho = "fovea-eval perceptual: ";

bool load(const std::string& path, foveation::ImageRgb* image, std::string* error) {
  const bool pfm = path.size() >= 4 && path.compare(path.size() - 4, 4, ".pfm") == 0;
  return pfm ? read_pfm(path, image, error) : toolkit::read_image(path, toolkit::PngValues::display, image, error);
}

// What is wrong with the arguments and images ("" when nothing); the display into *d.
std::string problem(const PerceptualCommand& c, const foveation::ImageRgb& test, const foveation::ImageRgb& ref,
                    PerceptualDisplay* d) {
  if (test.width_px != ref.width_px || test.height_px != ref.height_px)
    return "--test is " + std::to_string(test.width_px) + "x" + std::to_string(test.height_px) + ", --reference " +
           std::to_string(ref.width_px) + "x" + std::to_string(ref.height_px) + ": they must be the same size";
  if (test.width_px < 8 || test.height_px < 8) return "the images must be at least 8x8 pixels";
  if (!c.gaze_px) return "--gaze X,Y (pixels) is required";
  if (!(c.gaze_px->x >= 0.0f && c.gaze_px->y >= 0.0f && c.gaze_px->x <= float(test.width_px) &&
        c.gaze_px->y <= float(test.height_px)))
    return "--gaze is off the " + std::to_string(test.width_px) + "x" + std::to_string(test.height_px) + " image";
  if (c.fov_deg && c.ppd) return "give --fov-deg or --ppd, not both";
  if (c.fov_deg && !(*c.fov_deg > 0.0 && *c.fov_deg < 180.0)) return "--fov-deg must be in (0, 180) degrees";
  if (c.ppd && !(*c.ppd > 0.0 && std::isfinite(*c.ppd))) return "--ppd must be positive";
  if (!(c.white_cd_m2 > 0.0 && std::isfinite(c.white_cd_m2))) return "--white-cd-m2 must be positive";
  if (c.eye != "left" && c.eye != "right") return "--eye must be left or right";
  if (!(c.flicker_hz >= 0.0 && std::isfinite(c.flicker_hz))) return "--flicker-hz must be finite and >= 0";
  // A flat screen of horizontal field H: D = (W / 2) / tan(H / 2) pixels, D pi / 180 per degree.
  const double to_rad = std::numbers::pi / 180.0;
  d->pixels_per_deg = c.fov_deg ? 0.5 * test.width_px / std::tan(0.5 * *c.fov_deg * to_rad) * to_rad : c.ppd.value_or(20.0);
  d->white_luminance_cd_m2 = c.white_cd_m2;
  d->black_luminance_cd_m2 = std::min(d->black_luminance_cd_m2, 0.5 * c.white_cd_m2);
  d->eye = c.eye == "left" ? Eye::kLeft : Eye::kRight;
  d->input = PerceptualInput::kSrgbEncoded;  // a PNG's bytes, the price list's PFMs: sRGB-encoded display values
  return "";
}

// How many times above threshold the difference is, when asked for: the whole image's, and each
// ring's (empty unless asked for).
struct Multiples {
  std::optional<double> image;
  std::vector<double> rings;
};

// A ring's threshold multiple; none when not asked for or the ring has no pixels (the table skips it).
std::optional<double> ring_multiple(const PerceptualResult& r, const Multiples& m, std::size_t i) {
  if (i >= m.rings.size() || r.rings[i].pixels == 0) return std::nullopt;
  return m.rings[i];
}

// The threshold multiples, when asked for: null (JSON) / left out (table) otherwise.
nlohmann::ordered_json result_json(const PerceptualDisplay& d, double flicker_hz, glm::vec2 gaze,
                                   const PerceptualResult& r, const Multiples& multiples) {
  const auto number_or_null = [](const std::optional<double>& v) {
    return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json();
  };
  nlohmann::ordered_json rings = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.rings.size(); ++i) {
    const PerceptualRing& ring = r.rings[i];
    rings.push_back(
        {{"from_deg", ring.from_deg},
         {"to_deg", std::isfinite(ring.to_deg) ? nlohmann::ordered_json(ring.to_deg) : nlohmann::ordered_json()},
         {"pixels", ring.pixels},
         {"p_detect_mean", ring.p_mean},
         {"p_detect_max", ring.p_max},
         {"p_detect_share", ring.detected_fraction},
         {"threshold_multiple", number_or_null(ring_multiple(r, multiples, i))}});
  }
  return {{"width", r.width_px},
          {"height", r.height_px},
          {"gaze", {gaze.x, gaze.y}},
          {"pixels_per_deg", d.pixels_per_deg},
          {"white_cd_m2", d.white_luminance_cd_m2},
          {"flicker_hz", flicker_hz},
          {"p_detect_mean", r.p_mean},
          {"p_detect_max", r.p_max},
          {"p_detect_share", r.detected_fraction},
          {"threshold_multiple", number_or_null(multiples.image)},
          {"rings", rings}};
}

void print_table(const PerceptualResult& r, const Multiples& multiples, std::ostream& out) {
  char line[160];
  const bool per_ring = !multiples.rings.empty();
  out << "ring (deg)   pixels   P mean   P max   share P>=0.5" << (per_ring ? "   threshold multiple" : "") << "\n";
  for (std::size_t i = 0; i < r.rings.size(); ++i) {
    const PerceptualRing& g = r.rings[i];
    if (g.pixels == 0) continue;
    std::snprintf(line, sizeof line, "%-10s %8llu   %.4f   %.4f   %.4f", ring_name(i).c_str(),
                  static_cast<unsigned long long>(g.pixels), g.p_mean, g.p_max, g.detected_fraction);
    out << line;
    if (per_ring) std::snprintf(line, sizeof line, "         %.3g", *ring_multiple(r, multiples, i)), out << line;
    out << "\n";
  }
  std::snprintf(line, sizeof line, "%-10s %8zu   %.4f   %.4f   %.4f\n", "image", r.p_detect.size(), r.p_mean, r.p_max,
                r.detected_fraction);
  out << line;
  if (!multiples.image) return;
  std::snprintf(line, sizeof line, "threshold multiple %.3g (P max 0.5 at the difference divided by it)\n",
                *multiples.image);
  out << line;
}

}  // namespace

int run_perceptual(const PerceptualCommand& c, std::ostream& out, std::ostream& err) {
  foveation::ImageRgb test, ref;
  std::string error;
  if (c.test.empty() || c.reference.empty()) return err << kWho << "--test A and --reference B are required\n", 2;
  if (!load(c.test, &test, &error)) return err << kWho << "--test: " << error << "\n", 2;
  if (!load(c.reference, &ref, &error)) return err << kWho << "--reference: " << error << "\n", 2;
  PerceptualDisplay d;
  if (const std::string bad = problem(c, test, ref, &d); !bad.empty()) return err << kWho << bad << "\n", 2;
  foveation::Executor executor;
  PerceptualMetric metric;
  PerceptualResult r;
  PerceptualOptions options;
  options.temporal_freq_hz = c.flicker_hz;
  if (!PerceptualMetric::create(d, test.width_px, test.height_px, options, metric, error, &executor) ||
      !metric.evaluate(test, ref, *c.gaze_px, &executor, r, error))
    return err << kWho << error << "\n", 1;
  Multiples multiples;
  if ((c.threshold_multiple || c.ring_multiples) &&
      !metric.threshold_multiple(test, ref, *c.gaze_px, &executor, multiples.image.emplace(), error,
                                 c.ring_multiples ? &multiples.rings : nullptr))
    return err << kWho << error << "\n", 1;
  if (!c.heatmap_png.empty() && !write_detection_png(c.heatmap_png, r, &error)) return err << kWho << error << "\n", 1;
  if (c.json)
    out << result_json(d, c.flicker_hz, *c.gaze_px, r, multiples).dump(2) << "\n";
  else
    print_table(r, multiples, out);
  return 0;
}

void register_perceptual(CLI::App& app) {
  auto c = std::make_shared<PerceptualCommand>();
  auto gaze = std::make_shared<std::string>();
  auto fov = std::make_shared<double>(0.0), ppd = std::make_shared<double>(0.0);
  CLI::App* cmd = app.add_subcommand(
      "perceptual", "Would an observer fixating the gaze see the difference: detection probability per ring");
  // Checked by run_perceptual, not CLI11, so that every bad argument exits 2 with its message.
  cmd->add_option("--test", c->test, "Test image: PFM or PNG of sRGB-encoded display values (required)");
  cmd->add_option("--reference", c->reference, "Reference image, the same size (required)");
  cmd->add_option("--gaze", *gaze, "Gaze X,Y in pixels (required)");
  auto* fov_opt = cmd->add_option("--fov-deg", *fov, "Horizontal field of view of the image (degrees, flat screen)");
  auto* ppd_opt = cmd->add_option("--ppd", *ppd, "Pixels per degree at the gaze (default 20)");
  cmd->add_option("--white-cd-m2", c->white_cd_m2, "Luminance of display white (cd/m^2)")->capture_default_str();
  cmd->add_option("--eye", c->eye, "left or right (which visual field is temporal)")->capture_default_str();
  cmd->add_flag("--json", c->json, "Print JSON instead of the table");
  cmd->add_option("--out", c->heatmap_png, "Write the detection probability per pixel as a grey PNG");
  cmd->add_option("--flicker-hz", c->flicker_hz,
                  "The difference flickers at this frequency (Hz; the display's half frame rate: it alternates "
                  "every frame); 0: it is static")
      ->capture_default_str();
  cmd->add_flag("--threshold-multiple", c->threshold_multiple,
                "Also how many times above its detection threshold the difference is (a bisection: about 15 "
                "evaluations)");
  cmd->add_flag("--ring-multiples", c->ring_multiples,
                "Also each ring's threshold multiple, by its largest P (a bisection a ring: about 15 evaluations "
                "each); implies --threshold-multiple");
  cmd->callback([c, gaze, fov, ppd, fov_opt, ppd_opt] {
    if (!gaze->empty()) {
      try {
        c->gaze_px = render_view::parse_gaze_option("--gaze", *gaze);
      } catch (const CLI::ValidationError& e) {
        std::cerr << kWho << e.what() << "\n";
        throw CLI::RuntimeError(2);
      }
    }
    if (fov_opt->count() > 0) c->fov_deg = *fov;
    if (ppd_opt->count() > 0) c->ppd = *ppd;
    const int code = run_perceptual(*c, std::cout, std::cerr);
    if (code != 0) throw CLI::RuntimeError(code);
  });
}

}  // namespace foveart::eval
