// The temporal columns in the price list's outputs: the acceptance of issue
// #18 (peripheral flicker with TAA at least 5x below no TAA at equal rays, the
// 0-5 deg error no worse) for the reprojected TAA and the render cache, the reference floor's margins,
// temporal.csv and report.md's section. Input: run_pricelist_temporal's JSON.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <ostream>
#include <string>

namespace foveart::eval {

// The setting the headline reads: the layer's defaults (MSM k = 5, scale 1,
// pixel-grid fovea, 1 ray per point) when measured, else the first TAA setting.
inline constexpr const char* kTemporalHeadlineSetting = "msm_k5_s1_pixel-grid_r1";

// The temporal goal (peripheral flicker at least 5x lower, 0-5 deg no worse) for one TAA track against the TAA-off track at equal rays (tracks as
// sequence_track_json writes them): {"<m>_ratio"[ring] (off over the track) for m = flicker (at fixed
// pixels), flicker_tracked (along the motion) and flicker_csf (weighted by what the eye resolves),
// "peripheral_flicker_5x_lower", "peripheral_tracked_flicker_5x_lower", "peripheral_csf_flicker_5x_lower"
// (every ring beyond 20 deg at 5x or more), "psnr_minus_off_db"[ring], "central_error_no_worse" (no loss at
// 0-5 deg)}; null entries where a ring is empty.
nlohmann::ordered_json temporal_goal(const nlohmann::ordered_json& off, const nlohmann::ordered_json& history);

// values[key]'s ratios in the rings beyond 20 deg: "5.6x / 6.1x / 9.1x" ("-" for an empty ring).
std::string peripheral_ratios(const nlohmann::ordered_json& values, const std::string& key, int decimals = 1);
// PSNR gains in the rings within 5 deg (dB): "+12.6 / +11.8" ("-" for an empty ring).
std::string central_gains_db(const nlohmann::ordered_json& gains);

// {"setting", "<m>_ratio_off_over_reproject"[ring], "<m>_ratio_off_over_restart"[ring],
//  "<m>_ratio_off_over_<c>"[ring] for each control c of kSequenceControls (stable_blur,
//  taa_on_reference, sample_history, sample_history_kept, ray_cache, ray_cache_kept: motion_sequence.hpp)
//  for m = flicker (at fixed pixels),
//  flicker_tracked (along the motion) and flicker_csf (weighted by what the eye resolves),
//  "peripheral_flicker_5x_lower" (fixed pixels, beside the goal), "peripheral_tracked_flicker_5x_lower" (the goal),
//  "peripheral_csf_flicker_5x_lower", "psnr_reproject_minus_off_db"[ring], "central_error_no_worse",
//  "settled_periphery": {"frames", "settle_frames", "<m>_ratio_off_over_reproject",
//  "<m>_ratio_off_over_<c>" for each control c} (the periphery pooled over the settled frames, beside the goal;
//  absent without per-frame values), "render_cache": temporal_goal of the setting's render-cache track
//  (absent without it)}
// for one setting's tracks (null entries where a ring is empty); null when off, restart or reproject is missing.
nlohmann::ordered_json temporal_acceptance(const nlohmann::ordered_json& temporal, const std::string& setting);

// Per ring, how far the reference sequence's own contribution lies below the
// smallest flicker (at fixed pixels and along the motion) and the smallest error of any track (dB), and
// whether every ring is at least 10 dB below: {"flicker_margin_db", "error_margin_db", "floor_10db_below"};
// the same for the flicker weighted by what the eye resolves against its own floor, beside the goal's
// measures and not in floor_10db_below: {"csf_flicker_margin_db", "csf_floor_10db_below"}.
nlohmann::ordered_json temporal_sanity(const nlohmann::ordered_json& temporal);

// The headline's sentence on the acceptance ("" when it cannot be read).
std::string temporal_headline(const nlohmann::ordered_json& temporal, const nlohmann::ordered_json& acceptance);
// The headline's sentence on the render cache's goal (acceptance["render_cache"]; "" without it).
std::string temporal_render_cache_line(const nlohmann::ordered_json& acceptance);
// report.md's sentence on the flicker weighted by what the eye resolves (flicker_csf), beside the goal.
std::string temporal_csf_line(const nlohmann::ordered_json& acceptance);

// temporal.csv: one row per track. Error message or "".
std::string write_temporal_csv(const std::filesystem::path& file, const nlohmann::ordered_json& temporal);

// The peripheral band's flicker frame by frame (sequence_band_json) of the
// acceptance's setting — TAA off, restarting, reprojected, the TAA fed the
// reference, every ray since the last restart kept, and the reprojected TAA's
// restarts marked — at fixed pixels and
// along the motion, as PNGs in dir. "" or what could not be written; nothing
// is drawn without an acceptance or per-frame values (a resumed older run).
inline constexpr const char* kTemporalPlotFixed = "temporal_periphery_fixed.png";
inline constexpr const char* kTemporalPlotTracked = "temporal_periphery_tracked.png";
std::string write_temporal_plots(const std::filesystem::path& dir, const nlohmann::ordered_json& temporal,
                                 const nlohmann::ordered_json& acceptance);

// report.md's "Temporal columns" section.
void write_temporal_markdown(std::ostream& md, const nlohmann::ordered_json& temporal,
                             const nlohmann::ordered_json& acceptance, const nlohmann::ordered_json& sanity);

}  // namespace foveart::eval
