// fovea-eval bench-md: a benchmark program's JSON becomes a result file headed by
// the command that measured it and the machine, with a row per run.
#include <eval/bench_markdown.hpp>

#include <toolkit/machine.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace {

const char* kJson = R"({
  "context": {"date": "2026-11-28T23:00:00+00:00", "host_name": "vm", "num_cpus": 2, "mhz_per_cpu": 2600,
              "library_build_type": "release"},
  "benchmarks": [
    {"name": "BM_Gather/nearest", "run_type": "iteration", "iterations": 120, "real_time": 5.25,
     "cpu_time": 5.5, "time_unit": "ms", "points": 452379},
    {"name": "BM_Gather/msm", "run_type": "iteration", "iterations": 40, "real_time": 15.0, "cpu_time": 14.75,
     "time_unit": "ms"},
    {"name": "BM_Broken", "error_occurred": true, "error_message": "no scene"}
  ]})";

TEST(BenchMarkdown, HeadNamesCommandAndMachineAndEveryRunIsARow) {
  std::string error;
  const std::string md = foveart::eval::bench_markdown(nlohmann::json::parse(kJson), "interp_bench",
                                                       "build/bin/interp_bench --benchmark_filter=.", &error)
                             .value_or("");
  EXPECT_EQ(error, "");
  EXPECT_EQ(md.rfind("# interp_bench\n\nWritten by `build/bin/interp_bench --benchmark_filter=.` on ", 0), 0u) << md;
  EXPECT_NE(md.find(foveart::toolkit::machine_description()), std::string::npos) << md;
  EXPECT_NE(md.find("num_cpus 2;"), std::string::npos) << md;
  EXPECT_NE(md.find("| benchmark | time | CPU time | iterations | points |\n|---|---|---|---|---|\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| BM_Gather/nearest | 5.25 ms | 5.5 ms | 120 | 4.524e+05 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| BM_Gather/msm | 15 ms | 14.75 ms | 40 |  |"), std::string::npos) << md;
  EXPECT_NE(md.find("| BM_Broken | error: no scene |"), std::string::npos) << md;
}

TEST(BenchMarkdown, NotBenchmarkJsonIsAnError) {
  std::string error;
  EXPECT_EQ(foveart::eval::bench_markdown(nlohmann::json::parse(R"({"runs": []})"), "t", "c", &error), std::nullopt);
  EXPECT_NE(error.find("\"benchmarks\""), std::string::npos) << error;
  error.clear();
  EXPECT_EQ(
      foveart::eval::bench_markdown(nlohmann::json::parse(R"({"benchmarks": [{"iterations": 1}]})"), "t", "c", &error),
      std::nullopt);
  EXPECT_NE(error.find("without a name"), std::string::npos) << error;
}

TEST(MachineDescription, NamesCoresOsAndBuild) {
  const std::string m = foveart::toolkit::machine_description();
  EXPECT_NE(m.find(" cores; "), std::string::npos) << m;
  EXPECT_NE(m.find("Linux"), std::string::npos) << m;
  EXPECT_NE(m.find(CMAKE_BUILD_TYPE_FOR_TEST), std::string::npos) << m;
  EXPECT_EQ(foveart::toolkit::shell_quote("--out"), "--out");
  EXPECT_EQ(foveart::toolkit::shell_quote("a b"), "'a b'");
  EXPECT_EQ(foveart::toolkit::shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(foveart::toolkit::shell_quote(""), "''");
}

}  // namespace
