// Reading VK_LAYER_FOVEART_count's output (count_layer.cpp), without gtest (the
// tests' vk_counts.hpp and the GPU benchmark's report read it alike): the
// device records (one JSON object per line), who made each call (the innermost
// module on the caller's stack), frames split at a marker submission, and
// per-frame tallies of host submissions, waits, maps and flushes and of the
// work submitted (dispatches, barriers, ray-tracing launches), kept apart.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <map>
#include <ostream>
#include <string>
#include <vector>

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
      {"from_host_bytes", t.from_host_bytes}, {"from_host_texels", t.from_host_texels}};
  *os << "{";
  for (const auto& [name, value] : fields)
    if (value != 0) *os << " " << name << "=" << value;
  *os << " }";
}

// A frame's submitted work of one role: the commands recorded into the command
// buffers it submitted (not host calls; kept apart from Tally).
struct Work {
  uint64_t dispatches = 0, dispatches_indirect = 0, barriers = 0, trace_rays = 0;

  void add(const nlohmann::json& e) {
    const std::string call = e["call"];
    uint64_t* field = call == "vkCmdDispatch"           ? &dispatches
                      : call == "vkCmdDispatchIndirect" ? &dispatches_indirect
                      : call == "vkCmdPipelineBarrier"  ? &barriers
                      : call == "vkCmdTraceRaysKHR"     ? &trace_rays
                                                        : nullptr;
    if (field != nullptr) *field += e["items"].get<uint64_t>();
  }
  void add(const Work& w) {
    dispatches += w.dispatches;
    dispatches_indirect += w.dispatches_indirect;
    barriers += w.barriers;
    trace_rays += w.trace_rays;
  }
  bool operator==(const Work&) const = default;
};

// One frame's tallies by role.
using Frame = std::map<std::string, Tally>;

using IsMarker = std::function<bool(const nlohmann::json&, const std::string&)>;

// The complete frames of a device record, each a map role -> T (Tally or Work):
// frame i runs from its first marker event (every `markers_per_frame`-th) to the
// next frame's; what comes before the first marker (start-up) and from the last
// one on (the last frame and the shutdown) is left out.
template <class T>
std::vector<std::map<std::string, T>> split_frames_of(const nlohmann::json& record, const Roles& roles,
                                                      const IsMarker& is_marker, int markers_per_frame) {
  std::vector<std::map<std::string, T>> frames;
  int markers = 0;
  bool started = false;
  std::map<std::string, T> current;
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

inline std::vector<Frame> split_frames(const nlohmann::json& record, const Roles& roles, const IsMarker& is_marker,
                                       int markers_per_frame) {
  return split_frames_of<Tally>(record, roles, is_marker, markers_per_frame);
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
  }
  return t;
}

}  // namespace foveart::vk_count
