// Line and scatter plots as PNG (PLplot, "pngcairo" device). Errors are returned
// as messages naming the file; nothing throws.
#pragma once

#include <string>
#include <vector>

namespace foveart::toolkit {

struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  bool points = false;  // markers instead of a line
};

struct PlotSpec {
  std::string title;
  std::string x_label;
  std::string y_label;
  int width_px = 900;
  int height_px = 600;
  // The legend inside the axes' top right corner, or below the axes (for
  // series that fill the whole plot).
  bool legend_below = false;
};

// Whether some series has a point with finite x and y: what write_plot_png
// needs to draw anything (without one it returns an error).
bool has_finite_point(const std::vector<PlotSeries>& series);

// Writes a PNG with every series on shared axes and a legend.
std::string write_plot_png(const std::string& path, const PlotSpec& spec,
                           const std::vector<PlotSeries>& series);

}  // namespace foveart::toolkit
