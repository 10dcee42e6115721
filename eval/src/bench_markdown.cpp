#include <eval/bench_markdown.hpp>

#include <toolkit/machine.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <vector>

namespace foveart::eval {
namespace {

using Json = nlohmann::json;

// Keys of a run that are not counters.
bool is_counter(const std::string& key, const Json& value) {
  static const char* kFixed[] = {"name",
                                 "family_index",
                                 "per_family_instance_index",
                                 "run_name",
                                 "run_type",
                                 "repetitions",
                                 "repetition_index",
                                 "threads",
                                 "iterations",
                                 "real_time",
                                 "cpu_time",
                                 "time_unit",
                                 "aggregate_name",
                                 "aggregate_unit",
                                 "label",
                                 "error_occurred",
                                 "error_message"};
  for (const char* k : kFixed)
    if (key == k) return false;
  return value.is_number();
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// A cell: no '|' or newline may break the table.
std::string cell(std::string s) {
  for (char& c : s)
    if (c == '|' || c == '\n') c = ' ';
  return s;
}

}  // namespace

std::optional<std::string> bench_markdown(const Json& doc, const std::string& title, const std::string& command,
                                          std::string* error) {
  if (!doc.is_object() || !doc.contains("benchmarks") || !doc["benchmarks"].is_array()) {
    *error = "not Google Benchmark JSON (no \"benchmarks\" array)";
    return std::nullopt;
  }
  const Json& runs = doc["benchmarks"];
  std::vector<std::string> counters;
  for (const Json& r : runs) {
    if (!r.is_object() || !r.contains("name") || !r["name"].is_string()) {
      *error = "a run without a name in \"benchmarks\"";
      return std::nullopt;
    }
    for (const auto& [key, value] : r.items())
      if (is_counter(key, value) && std::find(counters.begin(), counters.end(), key) == counters.end())
        counters.push_back(key);
  }
  std::ostringstream md;
  md << "# " << title << "\n\n" << toolkit::result_header(command) << "\n";
  if (doc.contains("context") && doc["context"].is_object()) {
    const Json& c = doc["context"];
    md << "Google Benchmark's context:";
    for (const char* k : {"date", "host_name", "num_cpus", "mhz_per_cpu", "cpu_scaling_enabled", "library_build_type"})
      if (c.contains(k)) md << " " << k << " " << (c[k].is_string() ? c[k].get<std::string>() : c[k].dump()) << ";";
    if (c.contains("load_avg") && c["load_avg"].is_array()) md << " load_avg " << c["load_avg"].dump() << ";";
    md << "\n\n";
  }
  md << "| benchmark | time | CPU time | iterations";
  for (const std::string& k : counters) md << " | " << cell(k);
  md << " |\n|---|---|---|---";
  for (std::size_t i = 0; i < counters.size(); ++i) md << "|---";
  md << "|\n";
  for (const Json& r : runs) {
    const std::string unit = r.value("time_unit", std::string("ns"));
    md << "| " << cell(r["name"].get<std::string>());
    if (r.value("error_occurred", false)) {
      md << " | error: " << cell(r.value("error_message", std::string())) << " | | ";
    } else {
      md << " | " << number(r.value("real_time", 0.0)) << " " << unit << " | " << number(r.value("cpu_time", 0.0))
         << " " << unit << " | " << r.value("iterations", 0);
    }
    for (const std::string& k : counters) md << " | " << (r.contains(k) ? number(r[k].get<double>()) : "");
    md << " |\n";
  }
  return md.str();
}

void register_bench_md(CLI::App& app) {
  struct Args {
    std::string json, command, out, title;
  };
  auto a = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("bench-md", "A benchmark program's JSON as a markdown result file");
  cmd->add_option("--json", a->json, "Google Benchmark JSON (--benchmark_out_format=json)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--command", a->command, "The command that measured it, as run")->required();
  cmd->add_option("--out", a->out, "Markdown file to write")->required();
  cmd->add_option("--title", a->title, "Heading (default: the JSON file's name)");
  cmd->callback([a] {
    std::ifstream in(a->json);
    const Json doc = Json::parse(in, nullptr, false);
    std::string error = "not JSON";
    const std::string title = a->title.empty() ? std::filesystem::path(a->json).stem().string() : a->title;
    const std::optional<std::string> md =
        doc.is_discarded() ? std::nullopt : bench_markdown(doc, title, a->command, &error);
    if (!md) throw CLI::ValidationError("--json", a->json + ": " + error);
    std::ofstream out(a->out);
    out << *md;
    if (!out) throw CLI::ValidationError("--out", "cannot write " + a->out);
  });
}

}  // namespace foveart::eval
