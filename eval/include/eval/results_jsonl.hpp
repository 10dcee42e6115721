// The price list's resume files (results.jsonl, temporal.jsonl): one JSON
// object per measured setting, keyed by its "id".
#pragma once

#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace foveart::eval {

// The results already in `file` (none when it does not exist), by id. A line
// that is not a result is named on `err` and left out: measured again.
std::map<std::string, nlohmann::ordered_json> read_results_jsonl(const std::filesystem::path& file, std::ostream& err);

}  // namespace foveart::eval
