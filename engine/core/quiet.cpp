#include "core/quiet.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>

namespace keel::core {

std::mutex& library_mutex(std::string_view library) {
  static std::mutex guard;
  static std::map<std::string, std::unique_ptr<std::mutex>, std::less<>> mutexes;
  std::lock_guard<std::mutex> lock(guard);
  auto it = mutexes.find(library);
  if (it == mutexes.end()) it = mutexes.emplace(std::string(library), std::make_unique<std::mutex>()).first;
  return *it->second;
}

QuietStdout::QuietStdout() {
  std::fflush(stdout);
  saved_ = ::dup(STDOUT_FILENO);
  const int null = ::open("/dev/null", O_WRONLY);
  if (saved_ >= 0 && null >= 0) ::dup2(null, STDOUT_FILENO);
  if (null >= 0) ::close(null);
}

QuietStdout::~QuietStdout() {
  std::fflush(stdout);
  if (saved_ >= 0) {
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
}

}  // namespace keel::core
