// gaze-diag plots: gaze heatmap and yaw/pitch time series (PLplot, pngcairo).
#include <plstream.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <vector>

#include "diag.h"
#include "gaze_provider/gaze_math.h"

namespace foveart::gaze::diag {

namespace {

constexpr double kRangeDeg = 40.0;  // heatmap covers +-40 deg yaw and pitch
constexpr int kBins = 80;

bool writable(const std::string& path, std::string* error) {
  std::ofstream probe(path, std::ios::binary | std::ios::app);
  if (!probe) {
    if (error) *error = "cannot write " + path;
    return false;
  }
  return true;
}

void heatmap(const std::vector<GazeSample>& samples, const std::string& file) {
  std::vector<std::vector<PLFLT>> grid(kBins, std::vector<PLFLT>(kBins, 0.0));
  for (const GazeSample& s : samples) {
    if (!s.valid) continue;
    const YawPitchDeg yp = to_yaw_pitch_deg(s.combined_direction);
    const int ix = int(std::floor((yp.yaw_deg + kRangeDeg) / (2 * kRangeDeg) * kBins));
    const int iy = int(std::floor((yp.pitch_deg + kRangeDeg) / (2 * kRangeDeg) * kBins));
    if (ix >= 0 && ix < kBins && iy >= 0 && iy < kBins) grid[std::size_t(ix)][std::size_t(iy)] += 1.0;
  }
  PLFLT zmax = 1.0;
  for (auto& col : grid)
    for (PLFLT& v : col) {
      v = std::log1p(v);  // log scale: fixations dominate otherwise
      zmax = std::max(zmax, v);
    }
  std::vector<const PLFLT*> rows;
  for (auto& col : grid) rows.push_back(col.data());

  auto pls = std::make_unique<plstream>();
  pls->sdev("pngcairo");
  pls->sfnam(file.c_str());
  pls->spage(0, 0, 800, 800, 0, 0);
  pls->scolbg(255, 255, 255);
  pls->scol0(15, 0, 0, 0);  // axes and labels black on white
  pls->init();
  pls->col0(15);
  const PLFLT pos[] = {0.0, 0.3, 0.7, 1.0};
  const PLFLT r[] = {1.0, 0.2, 1.0, 0.6}, g[] = {1.0, 0.4, 0.8, 0.0}, b[] = {1.0, 1.0, 0.0, 0.0};
  pls->scmap1l(true, 4, pos, r, g, b, nullptr);
  pls->env(-kRangeDeg, kRangeDeg, -kRangeDeg, kRangeDeg, 1, 0);
  pls->image(rows.data(), kBins, kBins, -kRangeDeg, kRangeDeg, -kRangeDeg, kRangeDeg, 0.0, zmax, -kRangeDeg,
             kRangeDeg, -kRangeDeg, kRangeDeg);
  pls->col0(15);
  pls->box("bcnst", 0.0, 0, "bcnstv", 0.0, 0);
  pls->lab("yaw (deg, + right)", "pitch (deg, + up)", "gaze heatmap (log count)");
}

void timeseries(const std::vector<GazeSample>& samples, const std::string& file) {
  std::vector<PLFLT> t, yaw, pitch, t_invalid, y_invalid;
  const std::int64_t t0 = samples.empty() ? 0 : samples.front().device_time_ns;
  PLFLT lo = -5, hi = 5;
  for (const GazeSample& s : samples) {
    const PLFLT ts = PLFLT(s.device_time_ns - t0) * 1e-9;
    if (!s.valid) {
      t_invalid.push_back(ts);
      continue;
    }
    const YawPitchDeg yp = to_yaw_pitch_deg(s.combined_direction);
    t.push_back(ts);
    yaw.push_back(yp.yaw_deg);
    pitch.push_back(yp.pitch_deg);
    lo = std::min({lo, yp.yaw_deg, yp.pitch_deg});
    hi = std::max({hi, yp.yaw_deg, yp.pitch_deg});
  }
  y_invalid.assign(t_invalid.size(), lo);
  const PLFLT t_end = samples.size() > 1 ? PLFLT(samples.back().device_time_ns - t0) * 1e-9 : 1.0;

  auto pls = std::make_unique<plstream>();
  pls->sdev("pngcairo");
  pls->sfnam(file.c_str());
  pls->spage(0, 0, 1200, 500, 0, 0);
  pls->scolbg(255, 255, 255);
  pls->scol0(15, 0, 0, 0);  // axes and labels black on white
  pls->init();
  pls->col0(15);
  pls->env(0.0, std::max<PLFLT>(t_end, 1e-3), lo - 1, hi + 1, 0, 0);
  pls->lab("device time (s)", "angle (deg)", "gaze: yaw (red), pitch (blue), invalid (grey ticks)");
  pls->col0(1);
  if (!t.empty()) pls->line(PLINT(t.size()), t.data(), yaw.data());
  pls->col0(9);
  if (!t.empty()) pls->line(PLINT(t.size()), t.data(), pitch.data());
  pls->col0(7);
  if (!t_invalid.empty()) pls->poin(PLINT(t_invalid.size()), t_invalid.data(), y_invalid.data(), 1);
}

}  // namespace

bool write_plots(const std::vector<GazeSample>& samples, const std::string& prefix, std::string* error) {
  const std::string heat = prefix + "_heatmap.png", series = prefix + "_timeseries.png";
  if (!writable(heat, error) || !writable(series, error)) return false;
  heatmap(samples, heat);  // each plstream is ended (and its file closed) when destroyed
  timeseries(samples, series);
  return true;
}

}  // namespace foveart::gaze::diag
