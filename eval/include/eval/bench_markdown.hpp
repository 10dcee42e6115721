// Google Benchmark's JSON (--benchmark_out_format=json) as a markdown result
// file: the command that measured it and the machine at the head, then one
// table of its runs. `fovea-eval bench-md` (scripts/bench.sh) writes them.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace foveart::eval {

// The markdown of one benchmark program's JSON `doc`: "# title", the result header
// (toolkit::result_header(command)), the benchmark library's own context, and a table
// with a row per run (name, time, CPU time, iterations, then every counter it reports).
// Nullopt and *error set when `doc` is not Google Benchmark JSON.
std::optional<std::string> bench_markdown(const nlohmann::json& doc, const std::string& title,
                                          const std::string& command, std::string* error);

// `fovea-eval bench-md --json FILE --command CMD --out FILE.md [--title T]`.
void register_bench_md(CLI::App& app);

}  // namespace foveart::eval
