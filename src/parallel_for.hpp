#pragma once
// Private to the library: the span jobs of per-frame work (skinning, motor blending,
// deformation) split over one persistent pool of threads. A frame is a few milliseconds or less:
// starting threads per call (tens of microseconds each) cost more than the work they shared.

#include <algorithm>
#include <exception>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::detail {

/// Items of the smallest part worth a thread: below 2 × this a call runs inline. Measured here
/// (2 vCPUs shared with builds, load ≈ 12): a call of 8192 trivial items costs 15–90 µs more on
/// the pool than inline (thread-per-call: 0.3–1.6 ms more), the time of a few thousand vertices
/// of skinning, the cheapest job.
inline constexpr Eigen::Index kMinPartSize = 4096;

/// std::thread::hardware_concurrency() (at least 1), read once: glibc reads it from sysfs on
/// every call (7 µs measured on the CI machine, half a CesiumMan frame).
int hardware_threads() noexcept;

/// A job over [begin, end) without its type: what the pool's threads call.
struct SpanJob {
  void (*call)(void* job, Eigen::Index begin, Eigen::Index end);
  void* job;
};

/// Runs parts [0, parts) of [0, n) (part k is [n k / parts, n (k + 1) / parts)) on the calling
/// thread and the pool's (hardware threads − 1, started on first use), the parts taken in turn
/// until none is left. `errors[k]` receives part k's exception. A call from inside a part, or
/// while another thread's call holds the pool, runs its parts inline on the calling thread.
void run_parts(Eigen::Index n, int parts, SpanJob job, std::vector<std::exception_ptr>& errors);

/// Runs job(begin, end) over [0, n) in `threads` contiguous parts (0: all hardware threads), at
/// least `min_part` items a part (kMinPartSize suits a few hundred nanoseconds an item; costlier
/// items can take smaller parts); a single part runs inline. The first exception a job throws
/// (in part order) is rethrown here after every part has finished.
template <class Job>
void parallel_for(Eigen::Index n, int threads, Job&& job, Eigen::Index min_part = kMinPartSize) {
  const int t = static_cast<int>(std::min<Eigen::Index>(
      threads > 0 ? threads : hardware_threads(), std::max<Eigen::Index>(1, n / std::max<Eigen::Index>(1, min_part))));
  if (t <= 1) {
    job(Eigen::Index{0}, n);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(t));
  using Decayed = std::remove_reference_t<Job>;
  run_parts(n, t,
            {[](void* j, Eigen::Index begin, Eigen::Index end) { (*static_cast<Decayed*>(j))(begin, end); },
             const_cast<void*>(static_cast<const void*>(&job))},
            errors);
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace cgamesh::detail
