#include "parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <unistd.h>
#include <utility>

namespace cgamesh::detail {
namespace {

/// True on a thread while it runs a part: a parallel_for inside a part runs inline, since the
/// pool it would wait for is the one running it.
thread_local bool in_part = false;

/// One call's parts, on the calling thread's stack until every thread has left it.
struct Batch {
  Eigen::Index n;
  int parts;
  SpanJob job;
  std::vector<std::exception_ptr>* errors;
  std::atomic<int> next{0};  ///< the next part to take
  int finished = 0;          ///< parts done (under the pool's mutex)
  int inside = 0;            ///< pool threads that took the batch and have not left it (idem)
};

/// Takes parts of `batch` until none is left; returns how many it ran.
int take_parts(Batch& batch) noexcept {
  const bool outer = std::exchange(in_part, true);
  int ran = 0;
  for (int k; (k = batch.next.fetch_add(1, std::memory_order_relaxed)) < batch.parts; ++ran) {
    try {
      batch.job.call(batch.job.job, batch.n * k / batch.parts, batch.n * (k + 1) / batch.parts);
    } catch (...) {
      (*batch.errors)[static_cast<std::size_t>(k)] = std::current_exception();
    }
  }
  in_part = outer;
  return ran;
}

class ThreadPool {
 public:
  explicit ThreadPool(int workers) : pid_(getpid()) {
    for (int k = 0; k < workers; ++k) threads_.emplace_back([this] { work(); });
  }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  ~ThreadPool() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  /// Runs the batch with the pool; false when the pool is taken by another call or has no
  /// threads (one hardware thread, or a forked child: fork copies only the calling thread).
  bool try_run(Batch& batch) {
    if (threads_.empty() || getpid() != pid_) return false;
    const std::unique_lock busy(busy_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    {
      const std::lock_guard lock(mutex_);
      batch_ = &batch;
      ++generation_;
    }
    wake_.notify_all();
    const int ran = take_parts(batch);
    std::unique_lock lock(mutex_);
    batch.finished += ran;
    done_.wait(lock, [&] { return batch.finished == batch.parts && batch.inside == 0; });
    batch_ = nullptr;
    return true;
  }

 private:
  void work() {
    std::uint64_t seen = 0;
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || (batch_ != nullptr && generation_ != seen); });
      if (stop_) return;
      seen = generation_;
      Batch& batch = *batch_;
      ++batch.inside;
      lock.unlock();
      const int ran = take_parts(batch);
      lock.lock();
      batch.finished += ran;
      --batch.inside;
      if (batch.finished == batch.parts && batch.inside == 0) done_.notify_all();
    }
  }

  const pid_t pid_;
  std::mutex busy_;   ///< held by the call that owns the pool
  std::mutex mutex_;  ///< guards what follows and the current batch's counters
  std::condition_variable wake_, done_;
  Batch* batch_ = nullptr;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
  std::vector<std::thread> threads_;  ///< last: started once the rest is initialised
};

ThreadPool& pool() {
  static ThreadPool instance(hardware_threads() - 1);
  return instance;
}

}  // namespace

int hardware_threads() noexcept {
  static const int count = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return count;
}

void run_parts(Eigen::Index n, int parts, SpanJob job, std::vector<std::exception_ptr>& errors) {
  Batch batch{n, parts, job, &errors};
  if (!in_part && pool().try_run(batch)) return;
  take_parts(batch);
}

}  // namespace cgamesh::detail
