#include "core/names.hpp"

#include <fmt/format.h>

#include <span>
#include <stdexcept>

namespace keel::core {

void throw_unknown_name(std::string_view type, std::string_view text, const std::string_view* valid,
                        std::size_t count) {
  throw std::invalid_argument(
      fmt::format("unknown {} '{}' (valid: {})", type, text, fmt::join(std::span(valid, count), ", ")));
}

void throw_unnamed_value(std::string_view type, long long value) {
  throw std::invalid_argument(fmt::format("{}: value {} has no name", type, value));
}

}  // namespace keel::core
