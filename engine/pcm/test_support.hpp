// Helpers shared by the engine/pcm unit tests (not part of the library or its facade).
#pragma once

#include <stdexcept>
#include <string>

namespace keel::pcm::testing {

// The message of the std::invalid_argument that f throws, or kNoThrow when it throws none.
inline constexpr const char* kNoThrow = "<no throw>";
inline std::string message_of(auto&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return kNoThrow;
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace keel::pcm::testing
