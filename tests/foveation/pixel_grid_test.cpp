// The pixel-exact fovea (FoveaPattern::kPixelGrid): one point at every pixel
// centre where the eye resolves pixels (f_c >= f_d, thesis eqs. 2-4), the
// Poisson set beyond it, and never more points than pixels anywhere.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "foveation/display_model.hpp"
#include "foveation/gaze_mapping.hpp"
#include "foveation/point_density.hpp"
#include "foveation/point_set.hpp"
#include "foveation/visible_points.hpp"

namespace fv = foveart::foveation;

namespace {

struct NamedDisplay {
  std::string name;
  fv::DisplayModel display;
};

// Every preset (the thesis preset's display with the new pattern) and the
// displays of the acceptance list, from a low-resolution view to 4K.
std::vector<NamedDisplay> displays() {
  std::vector<NamedDisplay> out;
  for (const std::string& name : fv::display_preset_names()) {
    fv::DisplayModel d = *fv::display_preset(name);
    d.fovea_pattern = fv::FoveaPattern::kPixelGrid;
    out.push_back({name, d});
  }
  out.push_back({"128x128@85", fv::DisplayModel::from_fov(128, 128, 85.0)});
  out.push_back({"640x720@100", fv::DisplayModel::from_fov(640, 720, 100.0)});
  out.push_back({"2448x2448@100", fv::DisplayModel::from_fov(2448, 2448, 100.0)});
  out.push_back({"3840x2160@90", fv::DisplayModel::from_fov(3840, 2160, 90.0)});
  return out;
}

// Gazes that matter: centre, corners, edge midpoints, fractional positions, off-screen.
std::vector<glm::vec2> gazes(int w, int h) {
  const float fw = float(w), fh = float(h);
  return {{0.5f * fw, 0.5f * fh}, {0.0f, 0.0f},          {fw, 0.0f},         {0.0f, fh},
          {fw, fh},               {0.5f * fw, 0.0f},     {0.0f, 0.5f * fh},  {0.37f * fw + 0.31f, 0.61f * fh + 0.73f},
          {0.83f * fw + 0.5f, 0.21f * fh + 0.49f},       {-40.0f, 1.5f * fh}};
}

// Canvas pixels whose centre lies within radius_px of the centre of interest (W, H).
std::size_t pixel_centres_within(const fv::DisplayModel& d, double radius_px) {
  std::size_t n = 0;
  for (int y = 0; y < d.canvas_height_px(); ++y) {
    const double dy = double(y) + 0.5 - double(d.height_px);
    if (std::abs(dy) > radius_px) continue;
    for (int x = 0; x < d.canvas_width_px(); ++x) {
      const double dx = double(x) + 0.5 - double(d.width_px);
      n += std::sqrt(dx * dx + dy * dy) <= radius_px;
    }
  }
  return n;
}

bool at_pixel_centre(glm::vec2 p) { return p.x - std::floor(p.x) == 0.5f && p.y - std::floor(p.y) == 0.5f; }

}  // namespace

// The acceptance sweep: each display, scales 1-3, at every gaze: visible
// points <= pixels, the grid exactly the resolved disc, on pixel centres on
// the screen too, and no canvas pixel holding two points.
class PixelGrid : public ::testing::TestWithParam<NamedDisplay> {};

TEST_P(PixelGrid, NeverMorePointsThanPixelsForAnyScaleOrGaze) {
  const NamedDisplay& nd = GetParam();
  {
    for (double scale : {1.0, 2.0, 3.0}) {
      fv::DisplayModel d = nd.display;
      d.scale = scale;
      SCOPED_TRACE(nd.name + " scale " + std::to_string(scale));
      const fv::PointSet ps = fv::generate_point_set(d, 1);
      ASSERT_EQ(ps.footprint.size(), ps.size());
      EXPECT_EQ(ps.visible_margin_px, 0.0f);
      const double grid_radius_px = d.pixel_grid_radius_px();
      const glm::vec2 centre(float(d.width_px), float(d.height_px));
      std::size_t grid_points = 0;
      for (std::size_t i = 0; i < ps.size(); ++i) {
        const double dist = std::hypot(double(ps.position_px[i].x - centre.x), double(ps.position_px[i].y - centre.y));
        if (ps.on_pixel_grid(i)) {
          ++grid_points;
          ASSERT_TRUE(at_pixel_centre(ps.position_px[i])) << "grid point " << i << " off a pixel centre";
          ASSERT_TRUE(ps.in_exact_fovea(i)) << "grid point " << i << ": at scale 1 or more the grid is the fovea";
          ASSERT_LE(dist, grid_radius_px) << "grid point " << i;
        } else {
          ASSERT_GT(dist, grid_radius_px - 1.0) << "Poisson point " << i << " inside the grid";
        }
      }
      EXPECT_EQ(grid_points, pixel_centres_within(d, grid_radius_px));
      EXPECT_GT(grid_points, 0u);
      const fv::PointDensity density = fv::measure_point_density(ps, 8.0, 8.0);
      EXPECT_EQ(density.max_points_in_a_pixel, 1u);
      EXPECT_LE(density.max_points_per_px, 1.0);

      const std::size_t pixels = std::size_t(d.width_px) * std::size_t(d.height_px);
      for (const glm::vec2 gaze : gazes(d.width_px, d.height_px)) {
        const fv::GazeMapping mapping = fv::map_gaze(d.width_px, d.height_px, gaze);
        const fv::VisiblePoints visible = fv::select_visible_points(ps, mapping);
        EXPECT_LE(visible.size(), pixels) << "gaze " << gaze.x << "," << gaze.y;
        for (std::size_t v = 0; v < visible.size(); ++v) {
          if (!ps.on_pixel_grid(visible.point_index[v])) continue;
          ASSERT_TRUE(at_pixel_centre(visible.screen_px[v])) << "gaze " << gaze.x << "," << gaze.y;
        }
      }
    }
  }
}

// The pixel-exact fovea is the grid of the thesis's density: the whole grid at scale 1 and
// above; a denser scale widens the grid, not the fovea.
TEST_P(PixelGrid, ExactFoveaIsTheGridOfTheThesisDensity) {
  fv::DisplayModel thesis_density = GetParam().display;
  thesis_density.scale = 1.0;
  for (double scale : {0.5, 0.75, 1.0, 2.0}) {
    fv::DisplayModel d = GetParam().display;
    d.scale = scale;
    SCOPED_TRACE(GetParam().name + " scale " + std::to_string(scale));
    EXPECT_EQ(d.exact_fovea_radius_px(), (scale < 1.0 ? thesis_density : d).pixel_grid_radius_px());
    EXPECT_LE(d.exact_fovea_radius_px(), d.pixel_grid_radius_px());
    if (scale < 1.0 && std::isfinite(d.pixel_grid_radius_px()) && thesis_density.pixel_grid_radius_px() > 0.0) {
      EXPECT_LT(d.exact_fovea_radius_px(), d.pixel_grid_radius_px());
    }
  }
  fv::DisplayModel poisson = GetParam().display;
  poisson.fovea_pattern = fv::FoveaPattern::kThesisPoisson;
  EXPECT_EQ(poisson.exact_fovea_radius_px(), 0.0) << "no grid, no exact fovea";
}

INSTANTIATE_TEST_SUITE_P(Displays, PixelGrid, ::testing::ValuesIn(displays()),
                         [](const ::testing::TestParamInfo<NamedDisplay>& param) {
                           std::string name;
                           for (char c : param.param.name) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });
