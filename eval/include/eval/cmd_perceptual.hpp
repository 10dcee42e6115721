// `fovea-eval perceptual`: the perceptual metric (perceptual_metric.hpp) of one image pair at a
// gaze: per ring and whole-image detection probability, as text or JSON, a heat map, and on request
// how many times above threshold the difference is, in the whole image and per ring.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace CLI {
class App;
}

namespace foveart::eval {

void register_perceptual(CLI::App& app);

struct PerceptualCommand {
  std::string test, reference;     // PFM (display values) or any stb-readable image (PNG: display values / 255)
  std::optional<glm::vec2> gaze_px;  // required
  std::optional<double> fov_deg;   // horizontal field of view of the image; or
  std::optional<double> ppd;       // pixels per degree at the gaze (default 20)
  double white_cd_m2 = 100.0;
  std::string eye = "left";
  bool json = false;
  std::string heatmap_png;         // P per pixel, black 0 .. white 1
  bool threshold_multiple = false;  // also how many times above threshold the difference is
  bool ring_multiples = false;      // and each ring's (implies threshold_multiple)
  double flicker_hz = 0.0;          // the difference flickers at this frequency; 0: it is static
};

// 0 done; 2 bad arguments or unreadable / mismatched images (the message on err); 1 a failure after that.
int run_perceptual(const PerceptualCommand& c, std::ostream& out, std::ostream& err);

}  // namespace foveart::eval
