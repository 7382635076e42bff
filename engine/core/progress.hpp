// A progress bar on stderr for long runs: percentage, count, elapsed and estimated time left. Quiet when
// stderr is not a terminal (CI logs stay clean). Thread-safe: workers call advance() concurrently.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace keel::core {

class Progress {
 public:
  // `enabled` = -1: decide from isatty(stderr) and the KEEL_PROGRESS environment variable (0 = off, 1 = force
  // on).
  Progress(std::string label, std::size_t total, int enabled = -1);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(std::size_t n = 1);
  // Removes n units of work from the total: trials another shard of a sharded run computes (core/shard.hpp),
  // so that the bar and the time left describe this process's share.
  void skip(std::size_t n);
  // Prints the final line (100 %, total time) and stops drawing. Called by the destructor if not called
  // before.
  void finish();
  bool enabled() const { return enabled_; }
  std::size_t done() const { return done_.load(); }

 private:
  void draw(bool final_line);
  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<std::size_t> done_{0};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
};

// Formats seconds as "12.3s", "4m05s" or "1h02m".
std::string format_duration(double time_s);

}  // namespace keel::core
