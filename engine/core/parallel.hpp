// Parallel loop over independent trials. Each index is processed exactly once; callers write the result of
// trial i into slot i and reduce serially afterwards, so results do not depend on the thread count (DESIGN
// convention 9).
#pragma once

#include <cstddef>
#include <functional>

namespace keel::core {

class Progress;

// Number of worker threads used when 0 is requested: KEEL_THREADS if set, else
// std::thread::hardware_concurrency().
unsigned default_threads();

// Calls body(i) for i in [0, n) on `threads` threads (0 = default_threads()). Advances `progress` (may be
// null) by one per finished index. The outermost loop runs the BLAS on one thread while it lasts
// (core/blas.hpp). The first exception thrown by any body is rethrown here after all workers stopped.
void parallel_for(std::size_t n, const std::function<void(std::size_t)>& body, unsigned threads = 0,
                  Progress* progress = nullptr);

// Whether the calling thread is running a body of parallel_for (a nested loop; core/shard.hpp shards only the
// outermost trial loop).
bool inside_parallel_for();

}  // namespace keel::core
