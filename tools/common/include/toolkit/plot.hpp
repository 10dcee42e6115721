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
};

// Writes a PNG with every series on shared axes and a legend.
std::string write_plot_png(const std::string& path, const PlotSpec& spec,
                           const std::vector<PlotSeries>& series);

// Writes a heatmap PNG of a row-major grid (rows = y) with a colour bar.
std::string write_heatmap_png(const std::string& path, const PlotSpec& spec, int cols, int rows,
                              const std::vector<double>& values, double x_min, double x_max,
                              double y_min, double y_max);

}  // namespace foveart::toolkit
