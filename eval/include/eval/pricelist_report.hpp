// The price list's outputs from its measured settings: pricelist.json and
// .csv (one row per setting), the Pareto front per ring (time against PSNR),
// the full render at equal time for each foveated setting, plots, report.md
// and the headline.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace foveart::eval {

struct PricelistContext {
  nlohmann::ordered_json run;        // scene, view, gaze, machine, run time
  nlohmann::ordered_json reference;  // spp, residual_psnr per ring, ...
  std::string thesis_default;        // the setting id the headline calls the thesis's default
  std::string heatmap;               // the setting id of heatmap.png
  nlohmann::ordered_json temporal;   // run_pricelist_temporal's result; null: no temporal columns
  std::string command;               // the command line that measured it, for report.md's head
};

// "0-2.5", "2.5-5", ..., ">45": ring r's name in degrees.
std::string ring_name(std::size_t r);

// Indices of the settings on the Pareto front of (cost, accuracy): no other
// setting costs less or the same and is at least as accurate, one of them strictly.
// NaN entries are never on the front.
std::vector<std::size_t> pareto_front(const std::vector<double>& cost, const std::vector<double>& accuracy);

// The equal-time baseline of setting `of` in ring `ring`: among the full renders (with and
// without the image history) whose time fraction is no more than its own, the one with the highest PSNR
// in the ring (the cheaper on a tie). nullopt: no full render measured is that cheap.
std::optional<std::size_t> equal_time_full(const std::vector<nlohmann::ordered_json>& settings, std::size_t of,
                                           std::size_t ring);

// Whether the perceptual metric sees nothing a row adds to its full render at the same rays per
// pixel (unseen_in_every_ring on its rings' p_detect_max and p_detect_full_max); nullopt without
// perceptual columns or without a ring to judge (the full render is seen in every ring).
std::optional<bool> row_unseen(const nlohmann::ordered_json& setting);

// The content-aware comparison (pricelist.json's "detection"): each setting's "p_unseen" set, then per
// family of rows without history (eccentricity only; content-aware, any contrast and each; rays per
// point by content, each contrast) the rows, the unseen ones, the smallest unseen ray fraction
// (smallest_unseen) and the fewest rays with the rings seen there; and the goal (unseen at 10 % of
// the full render's rays or fewer): met or not, and per ring how many rows that cheap are seen.
nlohmann::ordered_json detection_json(std::vector<nlohmann::ordered_json>& settings);

// Writes pricelist.json, pricelist.csv, pareto_ring<R>.png, pricelist.png,
// report.md and, with temporal columns, temporal.csv into `dir`; *headline gets the summary sentence.
// False and *error naming the file that could not be written.
[[nodiscard]] bool write_pricelist(const std::filesystem::path& dir, const PricelistContext& context,
                                   std::vector<nlohmann::ordered_json> settings, std::string* headline,
                                   std::string* error);

}  // namespace foveart::eval
