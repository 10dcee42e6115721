#include "foveation/executor.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>

namespace foveart::foveation {

// One parallel_for in progress. Lives on the caller's stack; the caller
// leaves only when every index is finished and no worker holds the job.
struct Executor::Job {
  const std::function<void(std::size_t, unsigned)>* body = nullptr;
  std::size_t count = 0;
  std::atomic<std::size_t> next{0};      // next index to hand out
  std::atomic<std::size_t> finished{0};  // indices run (or skipped after a failure)
  std::atomic<bool> failed{false};
  std::exception_ptr error;              // first exception; written under the executor's mutex
  unsigned workers_inside = 0;           // pool threads running one of its indices; under the mutex
};

namespace {
// The executor whose thread this is (workers always; a caller while it runs
// its own indices): a parallel_for from inside a body runs inline.
thread_local const Executor* tl_inside = nullptr;
}  // namespace

Executor::Executor(unsigned thread_count) {
  if (thread_count > kMaxExecutorThreads)
    throw std::invalid_argument("an executor of " + std::to_string(thread_count) + " threads: at most " +
                                std::to_string(kMaxExecutorThreads));
  if (thread_count == 0) thread_count = std::clamp(std::thread::hardware_concurrency(), 1u, kMaxExecutorThreads);
  threads_.reserve(thread_count - 1);
  try {
    for (unsigned i = 1; i < thread_count; ++i) threads_.emplace_back([this, i] { worker_loop(i); });
  } catch (...) {
    stop_workers();  // a joinable thread left in threads_ would terminate the process
    throw;
  }
}

Executor::~Executor() {
  stop_workers();
}

void Executor::stop_workers() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

void Executor::worker_loop(unsigned worker) {
  tl_inside = this;
  std::unique_lock lock(mutex_);
  for (;;) {
    // The newest call first: a frame started beside a long table build gets
    // the workers as soon as each finishes its current index.
    Job* job = nullptr;
    wake_.wait(lock, [&] {
      if (stop_) return true;
      for (auto it = jobs_.rbegin(); it != jobs_.rend(); ++it) {
        if ((*it)->next.load(std::memory_order_relaxed) < (*it)->count) {
          job = *it;
          return true;
        }
      }
      return false;
    });
    if (stop_) return;
    const std::size_t index = job->next.fetch_add(1, std::memory_order_relaxed);
    if (index >= job->count) continue;
    ++job->workers_inside;
    lock.unlock();
    std::exception_ptr error;
    if (!job->failed.load(std::memory_order_relaxed)) {
      try {
        (*job->body)(index, worker);
      } catch (...) {
        error = std::current_exception();
      }
    }
    lock.lock();
    if (error && !job->error) job->error = error;
    if (error) job->failed.store(true, std::memory_order_relaxed);
    --job->workers_inside;
    job->finished.fetch_add(1, std::memory_order_acq_rel);
    wake_.notify_all();  // the caller waits on the same condition
  }
}

void Executor::parallel_for(std::size_t count, const std::function<void(std::size_t, unsigned)>& body) {
  if (count == 0) return;
  if (threads_.empty() || tl_inside == this || count == 1) {  // inline: no thread to share with
    for (std::size_t i = 0; i < count; ++i) body(i, 0);
    return;
  }
  Job job;
  job.body = &body;
  job.count = count;
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(&job);
  }
  wake_.notify_all();

  const Executor* const outer = tl_inside;
  tl_inside = this;
  std::exception_ptr error;
  for (std::size_t i; (i = job.next.fetch_add(1, std::memory_order_relaxed)) < count;) {
    if (!job.failed.load(std::memory_order_relaxed)) {
      try {
        body(i, 0);
      } catch (...) {
        error = std::current_exception();
        job.failed.store(true, std::memory_order_relaxed);
      }
    }
    job.finished.fetch_add(1, std::memory_order_acq_rel);
  }
  tl_inside = outer;

  std::unique_lock lock(mutex_);
  wake_.wait(lock, [&] { return job.finished.load(std::memory_order_acquire) == count && job.workers_inside == 0; });
  jobs_.erase(std::find(jobs_.begin(), jobs_.end(), &job));
  if (!error) error = job.error;
  lock.unlock();
  if (error) std::rethrow_exception(error);
}

void Executor::parallel_chunks(std::size_t n, std::size_t chunk,
                               const std::function<void(std::size_t, std::size_t, unsigned)>& body) {
  chunk = std::max<std::size_t>(1, chunk);
  parallel_for((n + chunk - 1) / chunk, [&](std::size_t c, unsigned worker) {
    body(c * chunk, std::min(n, (c + 1) * chunk), worker);
  });
}

}  // namespace foveart::foveation
