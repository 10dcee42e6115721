// Holding VK_LAYER_FOVEART_count's per-frame tallies (vk_records.hpp) to a
// per-frame budget in tests, and printing them.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "vk_records.hpp"

namespace foveart::vk_count {

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
