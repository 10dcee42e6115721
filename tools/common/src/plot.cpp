#include "toolkit/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include <plplot/plstream.h>

namespace foveart::toolkit {
namespace {

// PLplot aborts the process on an unwritable file: check first.
std::string check_writable(const std::string& path) {
  std::ofstream probe(path, std::ios::binary | std::ios::app);
  if (!probe) return "cannot write plot " + path;
  return {};
}

void light_theme(plstream& pls, const PlotSpec& spec, const std::string& path) {
  pls.sdev("pngcairo");
  pls.sfnam(path.c_str());
  pls.spage(0, 0, spec.width_px, spec.height_px, 0, 0);
  pls.scol0(0, 255, 255, 255);  // background
  pls.scol0(1, 0, 0, 0);        // axes and text
  pls.init();
}

const int kSeriesColours[][3] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {255, 127, 14},
                                 {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}};

}  // namespace

bool has_finite_point(const std::vector<PlotSeries>& series) {
  for (const auto& s : series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) return true;
    }
  }
  return false;
}

std::string write_plot_png(const std::string& path, const PlotSpec& spec, const std::vector<PlotSeries>& series) {
  if (auto err = check_writable(path); !err.empty()) return err;
  if (!has_finite_point(series)) return "cannot plot " + path + ": no finite data";
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]);
      x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]);
      y1 = std::max(y1, s.y[i]);
    }
  }
  if (x1 == x0) x1 = x0 + 1.0;
  if (y1 == y0) y1 = y0 + 1.0;
  const double pad = 0.05 * (y1 - y0);
  y0 = std::min(y0, 0.0) == 0.0 && y0 >= 0.0 ? 0.0 : y0 - pad;
  y1 += pad;

  plstream pls;
  light_theme(pls, spec, path);
  for (std::size_t i = 0; i < std::size(kSeriesColours); ++i) {
    pls.scol0(PLINT(i + 2), kSeriesColours[i][0], kSeriesColours[i][1], kSeriesColours[i][2]);
  }
  pls.col0(1);
  if (spec.legend_below) {
    // env()'s axes in a viewport that leaves the lower third to the legend.
    pls.adv(0);
    pls.vpor(0.1, 0.95, 0.42, 0.9);
    pls.wind(x0, x1, y0, y1);
    pls.box("bcgnst", 0.0, 0, "bcgnstv", 0.0, 0);
  } else {
    pls.env(x0, x1, y0, y1, 0, 2);  // 2: with grid
  }
  pls.lab(spec.x_label.c_str(), spec.y_label.c_str(), spec.title.c_str());
  std::vector<PLINT> opt, colours, styles, symbol_colours, symbol_numbers;
  std::vector<PLFLT> widths, scales;
  std::vector<const char*> texts, symbols;
  for (std::size_t si = 0; si < series.size(); ++si) {
    const auto& s = series[si];
    const PLINT colour = PLINT(2 + si % std::size(kSeriesColours));
    pls.col0(colour);
    const PLINT n = PLINT(std::min(s.x.size(), s.y.size()));
    if (s.points) {
      pls.poin(n, s.x.data(), s.y.data(), 17);
    } else {
      pls.width(2.0);
      pls.line(n, s.x.data(), s.y.data());
    }
    if (s.label.empty()) continue;  // drawn, but not in the legend
    opt.push_back(s.points ? PL_LEGEND_SYMBOL : PL_LEGEND_LINE);
    colours.push_back(colour);
    styles.push_back(1);
    widths.push_back(2.0);
    symbol_colours.push_back(colour);
    symbol_numbers.push_back(1);
    scales.push_back(1.0);
    texts.push_back(s.label.c_str());
    symbols.push_back("#(728)");
  }
  if (!texts.empty()) {
    PLFLT lw = 0, lh = 0;
    pls.col0(1);
    const PLINT position = spec.legend_below ? PL_POSITION_BOTTOM | PL_POSITION_OUTSIDE
                                             : PL_POSITION_RIGHT | PL_POSITION_TOP;
    pls.legend(&lw, &lh, PL_LEGEND_BACKGROUND | PL_LEGEND_BOUNDING_BOX, position,
               spec.legend_below ? 0.0 : 0.02, spec.legend_below ? 0.25 : 0.02, 0.1, 0, 0, 1, 0, 0,
               PLINT(texts.size()), opt.data(), 1.0, 1.0, 2.0, 1.0,
               colours.data(), texts.data(), nullptr, nullptr, nullptr, nullptr, colours.data(),
               styles.data(), widths.data(), symbol_colours.data(), scales.data(), symbol_numbers.data(),
               symbols.data());
  }
  return {};
}

}  // namespace foveart::toolkit
