// gaze-diag: inspect gaze hardware, measure a live gaze stream, analyse a trace.
//   gaze-diag list [--json]
//   gaze-diag stream --source SRC --seconds N [--record FILE] [--json]
//   gaze-diag report FILE [--json] [--png PREFIX]
// Exit codes: 0 ok, 1 bad input (message on stderr), 2 source failed or gave no samples.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <thread>
#include <vector>

#include "diag.h"
#include "gaze_provider/trace_stats.h"

using namespace foveart::gaze;

namespace {

// Every sample of `p` for `seconds` or until its stream ends, then stops it;
// each one also to `writer` if there is one. Progress each second on stderr unless json.
std::vector<GazeSample> collect_samples(GazeProvider& p, double seconds, bool json, TraceWriter* writer) {
  std::vector<GazeSample> all;
  std::vector<GazeSample> buf(1024);
  const auto t0 = std::chrono::steady_clock::now();
  const auto end = t0 + std::chrono::duration<double>(seconds);
  auto next_report = t0 + std::chrono::seconds(1);
  std::size_t at_last_report = 0;
  auto drain = [&] {
    for (std::size_t n; (n = p.read_raw(buf)) > 0;) {
      for (std::size_t i = 0; i < n; ++i) {
        all.push_back(buf[i]);
        if (writer) writer->write(buf[i]);
      }
    }
  };
  while (std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    drain();
    if (p.status().state == ProviderState::ended) break;
    if (!json && std::chrono::steady_clock::now() >= next_report) {
      const ProviderStatus st = p.status();
      std::fprintf(stderr, "  %5.1f s  %4zu samples/s  %s%s%s\n",
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                   all.size() - at_last_report, to_string(st.state), st.reason[0] ? ": " : "", st.reason.data());
      at_last_report = all.size();
      next_report += std::chrono::seconds(1);
    }
  }
  p.stop();
  drain();
  return all;
}

// The stream's statistics and the provider's final status, as JSON or text.
void print_stream_report(const TraceStats& stats, const GazeProvider& p, const ProviderStatus& st,
                         const std::string& source, bool json) {
  if (json) {
    std::string j = stats_to_json(stats, source);
    j.resize(j.size() - 3);  // reopen the object: drop "\n}\n"
    char extra[512];
    std::snprintf(extra, sizeof extra,
                  ",\n  \"nominal_rate_hz\": %.3f,\n  \"status\": \"%s\",\n  \"status_reason\": \"%s\",\n"
                  "  \"disconnects\": %llu,\n  \"raw_dropped\": %llu\n}\n",
                  p.nominal_rate_hz(), to_string(st.state), st.reason.data(),
                  static_cast<unsigned long long>(st.disconnects), static_cast<unsigned long long>(st.raw_dropped));
    std::cout << j << extra;
  } else {
    std::cout << stats_to_text(stats, source) << "status          " << to_string(st.state)
              << (st.reason[0] ? std::string(": ") + st.reason.data() : std::string()) << "\n";
  }
}

int run_stream(const std::string& source, double seconds, const std::string& record, bool json,
               ProviderOptions options) {
  if (!(seconds > 0.0 && seconds <= 86400.0)) {
    std::fprintf(stderr, "gaze-diag: --seconds must be in (0, 86400]\n");
    return 1;
  }
  std::ofstream record_file;
  std::unique_ptr<TraceWriter> writer;
  if (!record.empty()) {
    record_file.open(record, std::ios::binary | std::ios::trunc);
    if (!record_file) {
      std::fprintf(stderr, "gaze-diag: cannot write %s\n", record.c_str());
      return 1;
    }
    writer = std::make_unique<TraceWriter>(record_file);
  }
  CreateResult created = create_gaze_provider(source, options);
  if (!created) {
    std::fprintf(stderr, "gaze-diag: %s\n", created.error.c_str());
    return 2;
  }
  GazeProvider& p = *created.provider;
  std::string error;
  if (!p.start(&error)) {
    std::fprintf(stderr, "gaze-diag: %s\n", error.c_str());
    return 2;
  }
  const std::vector<GazeSample> all = collect_samples(p, seconds, json, writer.get());
  const ProviderStatus st = p.status();
  print_stream_report(compute_stats(all, {}, true, options.filters), p, st, source, json);
  if (writer && !writer->ok()) {
    std::fprintf(stderr, "gaze-diag: writing %s failed\n", record.c_str());
    return 1;
  }
  if (all.empty()) {
    std::fprintf(stderr, "gaze-diag: no samples from %s (%s%s%s)\n", source.c_str(), to_string(st.state),
                 st.reason[0] ? ": " : "", st.reason.data());
    return 2;
  }
  return 0;
}

int run_report(const std::string& file, bool json, const std::string& png, const FilterConfig& filters) {
  TraceError error;
  auto trace = read_trace_file(file, &error);
  if (!trace) {
    std::fprintf(stderr, "gaze-diag: %s\n", error.to_string().c_str());
    return 1;
  }
  if (trace->rows.empty()) {
    std::fprintf(stderr, "gaze-diag: %s: the trace has a header but no samples\n", file.c_str());
    return 1;
  }
  if (trace->skipped_non_monotonic)
    std::fprintf(stderr, "gaze-diag: %s: skipped %llu rows whose device time does not increase (first: line %zu)\n",
                 file.c_str(), static_cast<unsigned long long>(trace->skipped_non_monotonic),
                 trace->first_skipped_line);
  const TraceStats stats = compute_stats(*trace, filters);
  std::cout << (json ? stats_to_json(stats, file) : stats_to_text(stats, file));
  if (!png.empty()) {
    std::vector<GazeSample> samples;
    for (const TraceRow& r : trace->rows) samples.push_back(r.sample);
    std::string perr;
    if (!diag::write_plots(samples, png, &perr)) {
      std::fprintf(stderr, "gaze-diag: %s\n", perr.c_str());
      return 1;
    }
    if (!json) std::cout << "plots           " << png << "_heatmap.png, " << png << "_timeseries.png\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  CLI::App app{"gaze-diag: inspect gaze hardware, measure gaze streams, analyse gaze traces"};
  app.require_subcommand(1);
  ProviderOptions options;
  std::string hid_layout;
  bool json = false;

  CLI::App* list = app.add_subcommand("list", "USB and HID devices, FOVE client library availability");
  list->add_flag("--json", json, "JSON output");
  list->add_option("--fove-library", options.fove.library_path, "FOVE client library to try");

  CLI::App* stream = app.add_subcommand("stream", "measure a live gaze source");
  std::string source = "sim", record;
  double seconds = 5.0;
  bool fast = false;
  stream->add_option("--source", source, "sim | sim:SEED | replay:FILE | fove | hid | hid:VID:PID")->required();
  stream->add_option("--seconds", seconds, "how long to stream")->required();
  stream->add_option("--record", record, "write the raw samples as a trace (CSV)");
  stream->add_flag("--json", json, "JSON output");
  stream->add_flag("--fast", fast, "replay: as fast as possible instead of original timing");
  stream->add_option("--fove-library", options.fove.library_path, "FOVE client library path");
  stream->add_option("--hid-layout", hid_layout, "HID report layout spec (see docs/gaze_provider.md)");

  CLI::App* report = app.add_subcommand("report", "statistics, accuracy and plots of a recorded trace");
  std::string file, png;
  report->add_option("file", file, "trace CSV")->required();
  report->add_flag("--json", json, "JSON output");
  report->add_option("--png", png, "write PREFIX_heatmap.png and PREFIX_timeseries.png");

  CLI11_PARSE(app, argc, argv);

  if (!hid_layout.empty()) {
    std::string error;
    auto layout = HidReportLayout::parse(hid_layout, &error);
    if (!layout) {
      std::fprintf(stderr, "gaze-diag: %s\n", error.c_str());
      return 1;
    }
    options.hid.layout = *layout;
  }
  options.replay.original_timing = !fast;
  if (*list) return diag::run_list(options.fove, json);
  if (*stream) return run_stream(source, seconds, record, json, options);
  if (*report) return run_report(file, json, png, options.filters);
  return 1;
} catch (const std::exception& e) {
  std::fprintf(stderr, "gaze-diag: %s\n", e.what());
  return 1;
}
