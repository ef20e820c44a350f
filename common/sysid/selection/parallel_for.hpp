#pragma once
// Independent tasks on several threads, with results that do not depend on how many: task i
// writes only its own slot, and the first exception by task index (not by time) is rethrown
// after every thread has joined. Used where odonata-fit trains independent candidates
// (docs/identifier.md §9).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace odonata::sysid {

/// Worker threads for `requested` (0: every core the machine reports, at least 1).
inline unsigned ResolveThreads(unsigned requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

/// Runs task(i) for i in [0, count) on up to `threads` threads (the caller's among them).
inline void ParallelFor(std::size_t count, unsigned threads,
                        const std::function<void(std::size_t)>& task) {
  std::vector<std::exception_ptr> errors(count);
  std::atomic<std::size_t> next{0};
  auto work = [&]() {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        task(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  const std::size_t helpers = std::min<std::size_t>(count, std::max(1u, threads)) > 0
                                  ? std::min<std::size_t>(count, std::max(1u, threads)) - 1
                                  : 0;
  std::vector<std::thread> pool;
  pool.reserve(helpers);
  for (std::size_t t = 0; t < helpers; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace odonata::sysid
