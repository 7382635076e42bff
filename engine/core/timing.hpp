// Wall-clock durations in seconds (docs/DESIGN.md: durations are double seconds named *_time_s).
#pragma once

#include <chrono>

namespace keel::core {

using Clock = std::chrono::steady_clock;

// Seconds elapsed since t0 on the steady clock.
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace keel::core
