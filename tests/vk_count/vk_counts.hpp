// Reading VK_LAYER_FOVEART_count's output (count_layer.cpp): the device records
// (one JSON object per line), who made each call (the innermost module on the
// caller's stack), frames split at a marker submission, per-frame tallies of
// host submissions, waits, maps and flushes, the work submitted (dispatches,
// barriers, ray-tracing launches), and a per-frame budget to hold them to.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace foveart::vk_count {

// Every device record in a counts file, in the order the devices were destroyed.
inline std::vector<nlohmann::json> read_records(const std::filesystem::path& file) {
  std::vector<nlohmann::json> records;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) records.push_back(nlohmann::json::parse(line, nullptr, false));
  return records;
}

// Who made a call, from its caller chain (innermost module first): "layer" (the
// OpenXR layer), "engine" (the app's code called back by the layer: the GPU
// engine), "runtime" (the simulated runtime), "app" (the program itself), else
// the innermost module's file name.
struct Roles {
  std::string program;                              // the program's file name
  std::string layer = "libXrApiLayer_foveart.so";  // the OpenXR layer's
  std::string runtime = "libfoveart_sim_runtime.so";
};

inline std::string role_of(const nlohmann::json& event, const Roles& roles) {
  const auto& chain = event["chain"];
  if (chain.empty()) return "?";
  const std::string inner = chain[0].get<std::string>();
  if (inner == roles.layer) return "layer";
  if (inner == roles.runtime) return "runtime";
  if (inner == roles.program) {
    for (const auto& m : chain)
      if (m.get<std::string>() == roles.layer) return "engine";
    return "app";
  }
  return inner;
}

// A frame's host calls of one role, summed.
struct Tally {
  uint64_t submissions = 0;          // vkQueueSubmit and vkQueueSubmit2 calls
  uint64_t command_buffers = 0;      // in them
  uint64_t waits_this_frame = 0;     // fence waits on the newest submission of a queue, queue and device idle
                                     // waits, semaphore waits, query results with VK_QUERY_RESULT_WAIT_BIT
  uint64_t waits_older_frame = 0;    // fence waits on an earlier submission (a frame still in flight)
  uint64_t waits_unsubmitted = 0;    // fence waits on a fence never submitted or reset since
  uint64_t fence_polls = 0;          // vkGetFenceStatus
  uint64_t query_reads = 0;          // vkGetQueryPoolResults without the wait bit
  uint64_t maps = 0, mapped_bytes = 0;
  uint64_t unmaps = 0;
  uint64_t invalidates = 0, invalidated_bytes = 0;
  uint64_t flushes = 0, flushed_bytes = 0;
  // Submitted copies into (to_host) or out of (from_host) memory mapped when recorded:
  // bytes of buffer copies, texels of image copies.
  uint64_t copies_to_host = 0, to_host_bytes = 0, to_host_texels = 0;
  uint64_t copies_from_host = 0, from_host_bytes = 0, from_host_texels = 0;
  // The work in the command buffers submitted (recorded commands, not host calls).
  uint64_t dispatches = 0, dispatches_indirect = 0, barriers = 0, trace_rays = 0;

  void add(const nlohmann::json& e) {
    const std::string call = e["call"], kind = e["kind"];
    const uint64_t bytes = e["bytes"];
    if (call == "vkQueueSubmit" || call == "vkQueueSubmit2") {
      ++submissions;
      command_buffers += e["command_buffers"].get<uint64_t>();
    } else if (call == "vkWaitForFences") {
      (kind == "this_frame" ? waits_this_frame : kind == "older_frame" ? waits_older_frame : waits_unsubmitted) += 1;
    } else if (call == "vkQueueWaitIdle" || call == "vkDeviceWaitIdle" || call == "vkWaitSemaphores") {
      ++waits_this_frame;
    } else if (call == "vkGetQueryPoolResults") {
      (kind == "wait" ? waits_this_frame : query_reads) += 1;
    } else if (call == "vkGetFenceStatus") {
      ++fence_polls;
    } else if (call == "vkMapMemory") {
      ++maps;
      mapped_bytes += bytes;
    } else if (call == "vkUnmapMemory") {
      ++unmaps;
    } else if (call == "vkInvalidateMappedMemoryRanges") {
      ++invalidates;
      invalidated_bytes += bytes;
    } else if (call == "vkFlushMappedMemoryRanges") {
      ++flushes;
      flushed_bytes += bytes;
    } else if (call == "copy_to_host") {
      copies_to_host += e["items"].get<uint64_t>();
      to_host_bytes += bytes;
      to_host_texels += e["texels"].get<uint64_t>();
    } else if (call == "copy_from_host") {
      copies_from_host += e["items"].get<uint64_t>();
      from_host_bytes += bytes;
      from_host_texels += e["texels"].get<uint64_t>();
    } else if (call == "vkCmdDispatch") {
      dispatches += e["items"].get<uint64_t>();
    } else if (call == "vkCmdDispatchIndirect") {
      dispatches_indirect += e["items"].get<uint64_t>();
    } else if (call == "vkCmdPipelineBarrier") {
      barriers += e["items"].get<uint64_t>();
    } else if (call == "vkCmdTraceRaysKHR") {
      trace_rays += e["items"].get<uint64_t>();
    }
  }
  bool operator==(const Tally&) const = default;
};

// How gtest prints a Tally (the non-zero fields).
inline void PrintTo(const Tally& t, std::ostream* os) {
  const std::pair<const char*, uint64_t> fields[] = {
      {"submissions", t.submissions},   {"command_buffers", t.command_buffers},
      {"waits_this_frame", t.waits_this_frame}, {"waits_older_frame", t.waits_older_frame},
      {"waits_unsubmitted", t.waits_unsubmitted}, {"fence_polls", t.fence_polls},
      {"query_reads", t.query_reads},   {"maps", t.maps},
      {"mapped_bytes", t.mapped_bytes}, {"unmaps", t.unmaps},
      {"invalidates", t.invalidates},   {"invalidated_bytes", t.invalidated_bytes},
      {"flushes", t.flushes},           {"flushed_bytes", t.flushed_bytes},
      {"copies_to_host", t.copies_to_host}, {"to_host_bytes", t.to_host_bytes},
      {"to_host_texels", t.to_host_texels}, {"copies_from_host", t.copies_from_host},
      {"from_host_bytes", t.from_host_bytes}, {"from_host_texels", t.from_host_texels},
      {"dispatches", t.dispatches},     {"dispatches_indirect", t.dispatches_indirect},
      {"barriers", t.barriers},         {"trace_rays", t.trace_rays}};
  *os << "{";
  for (const auto& [name, value] : fields)
    if (value != 0) *os << " " << name << "=" << value;
  *os << " }";
}

// One frame's tallies by role.
using Frame = std::map<std::string, Tally>;

// The complete frames of a device record: frame i runs from its first marker
// event (every `markers_per_frame`-th) to the next frame's; what comes before
// the first marker (start-up) and from the last one on (the last frame and the
// shutdown) is left out.
inline std::vector<Frame> split_frames(const nlohmann::json& record, const Roles& roles,
                                       const std::function<bool(const nlohmann::json&, const std::string&)>& is_marker,
                                       int markers_per_frame) {
  std::vector<Frame> frames;
  int markers = 0;
  bool started = false;
  Frame current;
  for (const auto& e : record["events"]) {
    const std::string role = role_of(e, roles);
    if (is_marker(e, role)) {
      if (markers % markers_per_frame == 0) {
        if (started) frames.push_back(current);
        current.clear();
        started = true;
      }
      ++markers;
    }
    if (started) current[role].add(e);
  }
  return frames;
}

// Two roles' tallies as one (e.g. the layer and the engine it calls back).
inline Tally sum(const Frame& f, std::initializer_list<const char*> roles) {
  Tally t;
  for (const char* r : roles) {
    auto it = f.find(r);
    if (it == f.end()) continue;
    const Tally& a = it->second;
    t.submissions += a.submissions;
    t.command_buffers += a.command_buffers;
    t.waits_this_frame += a.waits_this_frame;
    t.waits_older_frame += a.waits_older_frame;
    t.waits_unsubmitted += a.waits_unsubmitted;
    t.fence_polls += a.fence_polls;
    t.query_reads += a.query_reads;
    t.maps += a.maps;
    t.mapped_bytes += a.mapped_bytes;
    t.unmaps += a.unmaps;
    t.invalidates += a.invalidates;
    t.invalidated_bytes += a.invalidated_bytes;
    t.flushes += a.flushes;
    t.flushed_bytes += a.flushed_bytes;
    t.copies_to_host += a.copies_to_host;
    t.to_host_bytes += a.to_host_bytes;
    t.to_host_texels += a.to_host_texels;
    t.copies_from_host += a.copies_from_host;
    t.from_host_bytes += a.from_host_bytes;
    t.from_host_texels += a.from_host_texels;
    t.dispatches += a.dispatches;
    t.dispatches_indirect += a.dispatches_indirect;
    t.barriers += a.barriers;
    t.trace_rays += a.trace_rays;
  }
  return t;
}

// Per-frame maxima of host calls at the Vulkan boundary; nullopt: not limited.
struct HostBudget {
  std::optional<uint64_t> submissions, waits_this_frame, waits_older_frame, waits_unsubmitted, fence_polls,
      query_reads, maps, mapped_bytes, invalidates, invalidated_bytes, flushes, flushed_bytes, copies_to_host,
      copies_from_host;
};

// Expects `t` (frame `frame` of `who`) within `budget`, one failure per exceeded limit.
inline void expect_within(const Tally& t, const HostBudget& budget, const std::string& who, int frame) {
  auto check = [&](const char* what, uint64_t value, const std::optional<uint64_t>& max) {
    if (max.has_value()) {
      EXPECT_LE(value, *max) << who << ", frame " << frame << ": " << what << " per frame over the budget";
    }
  };
  check("submissions", t.submissions, budget.submissions);
  check("host waits on this frame's work", t.waits_this_frame, budget.waits_this_frame);
  check("host waits on an older frame", t.waits_older_frame, budget.waits_older_frame);
  check("host waits on unsubmitted fences", t.waits_unsubmitted, budget.waits_unsubmitted);
  check("vkGetFenceStatus polls", t.fence_polls, budget.fence_polls);
  check("vkGetQueryPoolResults reads", t.query_reads, budget.query_reads);
  check("vkMapMemory calls", t.maps, budget.maps);
  check("vkMapMemory bytes", t.mapped_bytes, budget.mapped_bytes);
  check("vkInvalidateMappedMemoryRanges calls", t.invalidates, budget.invalidates);
  check("vkInvalidateMappedMemoryRanges bytes", t.invalidated_bytes, budget.invalidated_bytes);
  check("vkFlushMappedMemoryRanges calls", t.flushes, budget.flushes);
  check("vkFlushMappedMemoryRanges bytes", t.flushed_bytes, budget.flushed_bytes);
  check("copies into mapped memory (read-backs)", t.copies_to_host, budget.copies_to_host);
  check("copies out of mapped memory (uploads)", t.copies_from_host, budget.copies_from_host);
}

// Prints one line per frame and role: the table a test reports.
inline void print_frames(const char* title, const std::vector<Frame>& frames) {
  std::printf("%s\n%-5s %-8s %6s %5s %6s %6s %6s %6s %6s %5s %10s %5s %10s %5s %10s %4s %10s %4s %10s\n", title,
              "frame", "who", "submit", "cbs", "wait:T", "wait:O", "wait:U", "polls", "query", "maps", "map B", "inval",
              "inval B", "flush", "flush B", "d2h", "d2h B|tx", "h2d", "h2d B|tx");
  for (std::size_t i = 0; i < frames.size(); ++i)
    for (const auto& [who, t] : frames[i])
      std::printf("%-5zu %-8s %6llu %5llu %6llu %6llu %6llu %6llu %6llu %5llu %10llu %5llu %10llu %5llu %10llu %4llu "
                  "%10llu %4llu %10llu\n",
                  i,
                  who.c_str(), static_cast<unsigned long long>(t.submissions),
                  static_cast<unsigned long long>(t.command_buffers),
                  static_cast<unsigned long long>(t.waits_this_frame),
                  static_cast<unsigned long long>(t.waits_older_frame),
                  static_cast<unsigned long long>(t.waits_unsubmitted), static_cast<unsigned long long>(t.fence_polls),
                  static_cast<unsigned long long>(t.query_reads), static_cast<unsigned long long>(t.maps),
                  static_cast<unsigned long long>(t.mapped_bytes), static_cast<unsigned long long>(t.invalidates),
                  static_cast<unsigned long long>(t.invalidated_bytes), static_cast<unsigned long long>(t.flushes),
                  static_cast<unsigned long long>(t.flushed_bytes), static_cast<unsigned long long>(t.copies_to_host),
                  static_cast<unsigned long long>(t.to_host_bytes + t.to_host_texels),
                  static_cast<unsigned long long>(t.copies_from_host),
                  static_cast<unsigned long long>(t.from_host_bytes + t.from_host_texels));
  std::printf(
      "(wait:T on this frame's work, wait:O on an older frame, wait:U on an unsubmitted fence; d2h/h2d: copies\n"
      " into/out of mapped memory, bytes of buffer copies plus texels of image copies)\n");
}

}  // namespace foveart::vk_count
