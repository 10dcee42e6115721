// A fixed pool of worker threads running index ranges: the engine callback's
// batches and the interpolation's rows. The calling thread works too.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace foveart::layer {

class WorkerPool {
 public:
  explicit WorkerPool(unsigned thread_count);  // 0: hardware concurrency
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(threads_.size()) + 1; }

  // Calls task(i) for every i in [0, count), spread over the pool; returns when
  // all are done. task must not throw (wrap it); one parallel_for at a time.
  void parallel_for(std::size_t count, const std::function<void(std::size_t)>& task);

 private:
  void run_tasks();
  void worker();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(std::size_t)>* task_ = nullptr;
  std::size_t count_ = 0;
  std::size_t next_ = 0;
  std::size_t finished_ = 0;
  std::size_t generation_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace foveart::layer
