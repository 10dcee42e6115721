// The renderer's foveation tables, one set per view size (width, height, horizontal
// span): looked up each frame, built on the renderer's one builder thread through
// foveation's cache (load_view_tables), least recently used sets evicted past four,
// a build nobody needs any more cancelled at its next progress report.
#include <algorithm>
#include <cmath>
#include <exception>
#include <string>

#include "layer/sampling_defaults.hpp"
#include "log.hpp"
#include "renderer_frames.hpp"

namespace foveart::layer {
namespace {

// Thrown from a table build's progress callback when nobody needs the build any
// more (renderer destroyed, key evicted). Not a std::exception: nothing on the
// way mistakes it for a build error.
struct BuildCancelled {};

// Table sets held at once: both eyes' current sizes and the previous ones. A
// view size changing every frame (dynamic resolution) evicts the least recently used.
constexpr std::size_t kMaxTableSets = 4;

foveation::InterpOptions interp_options(const RendererSettings& settings) {
  foveation::InterpOptions o;
  switch (settings.interpolation) {
    case XR_FOVEATED_INTERPOLATION_NEAREST_FOVEART: o.method = foveation::InterpMethod::nearest; break;
    case XR_FOVEATED_INTERPOLATION_RBF_FOVEART: o.method = foveation::InterpMethod::rbf; break;
    default: o.method = foveation::InterpMethod::msm; break;
  }
  o.k = o.method == foveation::InterpMethod::nearest ? 1 : static_cast<int>(settings.k);
  return o;
}

}  // namespace

FoveatedRenderer::Frames::Tables FoveatedRenderer::Frames::tables_for(const FoveartEyeView& view) {
  const double span_rad = static_cast<double>(view.angle_right_rad) - static_cast<double>(view.angle_left_rad);
  const TableKey key{view.width_px, view.height_px, std::llround(span_rad * 1e6)};
  std::unique_lock lock(build_mutex);
  auto it = tables.find(key);
  if (it == tables.end()) {
    while (tables.size() >= kMaxTableSets) evict_least_recently_used();
    foveation::PointSetKey psk;
    psk.display = foveation::display_of_view(view);
    psk.display.scale = static_cast<double>(settings.density_scale);
    psk.seed = kSampleSeed;
    log(LogLevel::Info, "foveated renderer: preparing tables for ", view.width_px, "x", view.height_px, " (cache ",
        cache ? cache->string() : std::string("none"), ")");
    it = tables.emplace(key, TableSlot{}).first;
    input.table_sets_resident = static_cast<uint32_t>(tables.size());
    build_queue.emplace_back(key, psk);
    build_wake.notify_one();
  }
  TableSlot& slot = it->second;
  slot.last_used = frame_index;
  if (settings.wait_for_tables) {
    build_done.wait(lock, [&] { return slot.state == SlotState::ready || slot.state == SlotState::failed; });
  }
  return Tables{slot.ready, slot.state == SlotState::failed};
}

void FoveatedRenderer::Frames::evict_least_recently_used() {
  auto victim = std::min_element(tables.begin(), tables.end(),
                                 [](const auto& a, const auto& b) { return a.second.last_used < b.second.last_used; });
  if (victim->second.state == SlotState::queued) {
    std::erase_if(build_queue, [&](const auto& entry) { return entry.first == victim->first; });
  } else if (victim->second.state == SlotState::building) {
    cancel_build = true;
  }
  tables.erase(victim);
  ++input.table_sets_evicted;
  input.table_sets_resident = static_cast<uint32_t>(tables.size());
  if (evicted_once.first()) {
    log(LogLevel::Info, "foveated renderer: the view size keeps changing; table sets beyond ", kMaxTableSets,
        " are dropped, least recently used first (logged once, counted in the stats)");
  }
}

void FoveatedRenderer::Frames::cache_problem(const std::string& message) {
  // foveation's loaders end a rejection with "; rebuilding"; anything else is a cache that cannot be written.
  const bool rejected = message.ends_with("; rebuilding");
  ++(rejected ? input.cache_files_rejected : input.cache_failures);
  LogOnce& once = rejected ? rejected_once : unwritable_once;
  const LogLevel level = once.first() ? LogLevel::Warn : LogLevel::Debug;
  log(level, "foveated renderer: ", rejected ? "cache file rejected: " : "cache not written: ", message,
      level == LogLevel::Warn ? " (logged once, counted in the stats)" : "");
}

void FoveatedRenderer::Frames::build_tables() {
  std::unique_lock lock(build_mutex);
  for (;;) {
    build_wake.wait(lock, [&] { return stop_building || !build_queue.empty(); });
    if (stop_building) return;
    const auto [key, psk] = build_queue.front();
    build_queue.pop_front();
    auto it = tables.find(key);
    if (it == tables.end()) continue;
    it->second.state = SlotState::building;
    cancel_build = false;
    lock.unlock();
    std::shared_ptr<const foveation::ViewTables> built;
    std::string error;
    bool cancelled = false;
    try {
      built = foveation::load_view_tables(
          cache, psk, interp_options(settings), executor, std::nullopt,
          [this](double) {
            if (cancel_build.load(std::memory_order_relaxed)) throw BuildCancelled{};
          },
          [this](const std::string& message) { cache_problem(message); });
    } catch (const BuildCancelled&) {
      cancelled = true;
    } catch (const std::exception& e) {
      error = e.what();
    }
    lock.lock();
    it = tables.find(key);
    if (cancelled) {
      log(LogLevel::Debug, "foveated renderer: table build for ", std::get<0>(key), "x", std::get<1>(key),
          " cancelled: nobody needs it any more");
    }
    if (it == tables.end() || cancelled) continue;  // evicted (or stopping): nobody waits for it
    if (built != nullptr) {
      it->second.state = SlotState::ready;
      it->second.ready = std::move(built);
    } else {
      it->second.state = SlotState::failed;
      ++input.table_builds_failed;
      log(LogLevel::Error, "foveated renderer: cannot build the foveation tables for ", std::get<0>(key), "x",
          std::get<1>(key), ": ", error, "; views of this size show the app's image (counted in the stats)");
    }
    build_done.notify_all();
  }
}

}  // namespace foveart::layer
