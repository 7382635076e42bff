// keel::app — the progress callback of the long operations (solve stages, the §2.6 pipeline).
#pragma once

#include <functional>
#include <string_view>

namespace keel::app {

/// Called with a short description of each stage as it starts (progress on long runs); may be empty.
using Progress = std::function<void(std::string_view stage)>;

}  // namespace keel::app
