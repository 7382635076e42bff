// Calling third-party C solvers that keep global state and print to stdout (DSDP prints with printf): one
// process-wide mutex per library, shared by every area that calls it, and a guard that points stdout at
// /dev/null while a call runs (keel's progress and logs go to stderr, result files are written by name).
#pragma once

#include <mutex>
#include <string_view>

namespace keel::core {

// The process-wide mutex of `library` (e.g. "dsdp"): the same object for the same name, from any area.
std::mutex& library_mutex(std::string_view library);

// Redirects file descriptor 1 to /dev/null for its lifetime (stdout flushed before and after).
class QuietStdout {
 public:
  QuietStdout();
  ~QuietStdout();
  QuietStdout(const QuietStdout&) = delete;
  QuietStdout& operator=(const QuietStdout&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace keel::core
