#include "core/progress.hpp"

#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace keel::core {

std::string format_duration(double time_s) {
  const double s = time_s < 0 ? 0.0 : time_s;
  if (s < 60) return fmt::format("{:.1f}s", s);
  const int whole = static_cast<int>(s);
  if (s < 3600) return fmt::format("{}m{:02}s", whole / 60, whole % 60);
  return fmt::format("{}h{:02}m", whole / 3600, (whole % 3600) / 60);
}

namespace {
bool decide_enabled(int requested) {
  if (requested >= 0) return requested != 0;
  if (const char* env = std::getenv("KEEL_PROGRESS")) {
    if (std::strcmp(env, "0") == 0) return false;
    if (std::strcmp(env, "1") == 0) return true;
  }
  return isatty(STDERR_FILENO) == 1;
}
}  // namespace

Progress::Progress(std::string label, std::size_t total, int enabled)
    : label_(std::move(label)), total_(total), enabled_(decide_enabled(enabled)) {
  start_ = last_draw_ = std::chrono::steady_clock::now();
}

Progress::~Progress() { finish(); }

void Progress::advance(std::size_t n) {
  done_.fetch_add(n);
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || finished_) return;
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(false);
}

void Progress::skip(std::size_t n) {
  std::lock_guard lock(mutex_);
  total_ -= std::min(n, total_);
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (enabled_) draw(true);
}

void Progress::draw(bool final_line) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::size_t done = final_line ? total_ : std::min(done_.load(), total_);
  const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  constexpr int width = 28;
  const int filled = static_cast<int>(frac * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.append(static_cast<std::size_t>(width - filled), '-');
  std::string tail;
  if (final_line) {
    tail = fmt::format("done in {}", format_duration(elapsed));
  } else if (done > 0) {
    tail = fmt::format("elapsed {}, left ~{}", format_duration(elapsed),
                       format_duration(elapsed * (1.0 - frac) / frac));
  } else {
    tail = fmt::format("elapsed {}", format_duration(elapsed));
  }
  fmt::print(stderr, "\r\033[K{} [{}] {:3}% {}/{} {}{}", label_, bar, static_cast<int>(frac * 100.0), done,
             total_, tail, final_line ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace keel::core
