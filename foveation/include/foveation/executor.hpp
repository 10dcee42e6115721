// The one executor for FoveaRT's parallel work (the model is pbrt-v4's
// ParallelFor): a fixed set of worker threads, started once by whoever owns
// the executor (the layer, one per foveated renderer; a tool, one per
// process) and injected into everything that runs in parallel — point set and
// table builds, the engine callback's ray batches, the gather, the temporal blend. Nothing
// that takes an Executor starts a thread.
//
// Why not oneTBB: its scheduler lives in an uninstrumented library, so
// ThreadSanitizer reports every hand-off of data to a TBB worker as a race
// (docs/threading.md); silencing that would blind TSan to every parallel
// body. This pool is small, instrumented and measured as fast.
//
// Threads: parallel_for may be called from several threads at once (e.g. a
// background table build beside a frame); the calls share the workers. A call
// made from inside a body runs inline on that thread. `Executor(1)` starts no
// thread: every parallel_for then runs on the caller alone.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace foveart::foveation {

// The most threads one executor runs: the layer's "threads" key and the tools' --threads.
inline constexpr unsigned kMaxExecutorThreads = 256;

class Executor {
 public:
  // thread_count: threads that work on a parallel_for, the caller included
  // (0 = hardware concurrency). Starts thread_count - 1 workers. Throws
  // std::invalid_argument above kMaxExecutorThreads, and std::system_error
  // when the system refuses a thread (the ones started are stopped first).
  explicit Executor(unsigned thread_count = 0);
  ~Executor();
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  // Threads that work on one parallel_for, the caller included: worker slots
  // passed to a body are in [0, thread_count()).
  unsigned thread_count() const { return static_cast<unsigned>(threads_.size()) + 1; }

  // Calls body(index, worker) for every index in [0, count) and returns when
  // all are done. `worker` is unique among the threads running this call at
  // the same time (0 = the caller), so bodies can index per-thread scratch.
  // Indices are handed out one at a time in increasing order: make each one a
  // chunk of work. The first exception a body throws is rethrown here after
  // every index has finished or been skipped.
  void parallel_for(std::size_t count, const std::function<void(std::size_t index, unsigned worker)>& body);

  // The same without the worker slot.
  void parallel_for(std::size_t count, const std::function<void(std::size_t index)>& body) {
    parallel_for(count, [&body](std::size_t index, unsigned) { body(index); });
  }

  // body(first, last) over [0, n) in chunks of `chunk` items (the last may be shorter).
  void parallel_chunks(std::size_t n, std::size_t chunk,
                       const std::function<void(std::size_t first, std::size_t last, unsigned worker)>& body);

 private:
  struct Job;
  void worker_loop(unsigned worker);
  void stop_workers();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::vector<Job*> jobs_;  // calls in progress, oldest first
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace foveart::foveation
