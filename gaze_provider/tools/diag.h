// gaze-diag internals shared by its subcommands.
#pragma once

#include <string>
#include <vector>

#include "gaze_provider/backends.h"
#include "gaze_provider/trace_csv.h"

namespace foveart::gaze::diag {

// `gaze-diag list`: USB (libusb), HID (hidapi) and FOVE library availability.
int run_list(const FoveConfig& fove, bool json);

// Writes PREFIX_heatmap.png and PREFIX_timeseries.png (PLplot, pngcairo).
// Returns false and a message on failure.
[[nodiscard]] bool write_plots(const std::vector<GazeSample>& samples, const std::string& prefix, std::string* error);

}  // namespace foveart::gaze::diag
