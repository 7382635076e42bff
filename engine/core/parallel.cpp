#include "core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/blas.hpp"
#include "core/progress.hpp"

namespace keel::core {

unsigned default_threads() {
  if (const char* env = std::getenv("KEEL_THREADS")) {
    const int v = std::atoi(env);
    if (v > 0) return static_cast<unsigned>(v);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

namespace {
thread_local int worker_depth = 0;  // > 0 while this thread runs parallel_for bodies
}  // namespace

bool inside_parallel_for() { return worker_depth > 0; }

void parallel_for(std::size_t n, const std::function<void(std::size_t)>& body, unsigned threads,
                  Progress* progress) {
  if (threads == 0) threads = default_threads();
  // The trials are the parallelism: their BLAS calls run on one thread (core/blas.hpp), at any thread count,
  // so that a trial's numbers do not depend on the machine's cores. A nested loop is already inside such a
  // guard.
  std::optional<SingleThreadedBlas> one_blas_thread;
  if (worker_depth == 0) one_blas_thread.emplace();
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(n, 1)));
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  // Small chunks keep the load balanced when trial costs vary (sweeps over trajectory length).
  const std::size_t chunk = std::max<std::size_t>(1, n / (static_cast<std::size_t>(threads) * 64));
  auto worker = [&] {
    ++worker_depth;
    struct Leave {
      ~Leave() { --worker_depth; }
    } leave;
    while (!failed.load(std::memory_order_relaxed)) {
      const std::size_t begin = next.fetch_add(chunk);
      if (begin >= n) return;
      const std::size_t end = std::min(n, begin + chunk);
      for (std::size_t i = begin; i < end; ++i) {
        try {
          body(i);
        } catch (...) {
          std::lock_guard lock(error_mutex);
          if (!error) error = std::current_exception();
          failed = true;
          return;
        }
        if (progress) progress->advance();
      }
    }
  };
  if (threads <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    pool.reserve(threads);
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace keel::core
