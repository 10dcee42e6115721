#include <eval/results_jsonl.hpp>

#include <fstream>
#include <ostream>

namespace foveart::eval {

std::map<std::string, nlohmann::ordered_json> read_results_jsonl(const std::filesystem::path& file, std::ostream& err) {
  std::map<std::string, nlohmann::ordered_json> done;
  std::ifstream in(file);
  std::string line;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.contains("id") || !j["id"].is_string()) {
      err << "fovea-eval pricelist: " << file.string() << " line " << line_no << " is not a result; measuring again\n";
      continue;
    }
    const std::string id = j["id"].get<std::string>();  // before the move: `=` evaluates its right side first
    done[id] = std::move(j);
  }
  return done;
}

}  // namespace foveart::eval
