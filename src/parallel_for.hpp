#pragma once
// Private to the library: the span jobs of per-frame work (skinning, deformation) split over
// threads.

#include <algorithm>
#include <exception>
#include <thread>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::detail {

/// Runs job(begin, end) over [0, n) in `threads` contiguous parts (0: all hardware threads), at
/// least 4096 items a part: below that, starting a thread costs more than it saves. The first
/// exception a job throws is rethrown here after every thread has joined.
template <class Job>
void parallel_for(Eigen::Index n, int threads, Job&& job) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int t = static_cast<int>(std::min<Eigen::Index>(threads > 0 ? threads : hw, std::max<Eigen::Index>(1, n / 4096)));
  if (t <= 1) {
    job(Eigen::Index{0}, n);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(t));
  for (int k = 0; k < t; ++k)
    pool.emplace_back([&, k] {
      try {
        job(n * k / t, n * (k + 1) / t);
      } catch (...) {
        errors[static_cast<std::size_t>(k)] = std::current_exception();
      }
    });
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace cgamesh::detail
