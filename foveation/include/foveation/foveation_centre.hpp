// Where a frame centres its point set. The point set moves with its centre,
// so a centre that follows every whole-pixel change of the gaze shifts the
// whole periphery's sample pattern at the tracker's noise and the eye's
// microsaccades: peripheral flicker. The centre is held while the gaze stays
// within a deadband of it (a fixation: microsaccades of 0.1-0.4 deg, drift,
// tracker noise) and jumps to the gaze as soon as it leaves the deadband or
// the gaze provider flags a saccade or a blink: no added latency for a real
// gaze shift. With the pixel-exact fovea (15.3 deg at FOVE, scale 1) a 1 deg
// deadband keeps the fixated point at least 14 deg inside the pixel grid.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace foveart::foveation {

class FoveationCentre {
 public:
  explicit FoveationCentre(double deadband_px = 0.0) : deadband_px_(deadband_px) {}

  // The centre for a frame whose gaze is gaze_px; jump: a saccade or blink.
  glm::vec2 update(glm::vec2 gaze_px, bool jump) {
    if (!has_centre_ || jump || double(glm::distance(centre_, gaze_px)) > deadband_px_) centre_ = gaze_px;
    has_centre_ = true;
    return centre_;
  }
  double deadband_px() const { return deadband_px_; }

 private:
  double deadband_px_;
  glm::vec2 centre_{};
  bool has_centre_ = false;
};

}  // namespace foveart::foveation
